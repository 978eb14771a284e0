// SPDX-License-Identifier: GPL-3.0-or-later
// The Newton contact solve's first stage (System::Settings::Method::Newton;
// the method and why the stage: ContactSolverNewton.cpp): the region model
// of l (each row kept in a region: stiction, sliding along a direction,
// separation) and the primal-dual active-set steps on it, the regions
// first the warm start's, then updated from each step's solution.
#include "ContactSolverNewtonImpl.H"

#include <cmath>

namespace nscd
{
namespace newton
{

void NewtonSolve::regions(std::vector<int>& reg) const
{
    reg.assign(NC, 2);
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        reg[k] = project(vc[k], r.vhatN, r.Rn, r.Rt, r.mu, false).region;
    }
}

void NewtonSolve::regionModel(const std::vector<int>& reg, const std::vector<Eigen::Vector3d>& slip,
                              Eigen::VectorXd& g)
{
    resetHessian();
    g = mass.cwiseProduct(v - vStar);
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        const double yn = -(vc[k](0) - r.vhatN) / r.Rn;
        Eigen::Vector3d f = Eigen::Vector3d::Zero(); // impulse gamma of the model
        Eigen::Matrix3d B = Eigen::Matrix3d::Zero(); // -d gamma/d v_c
        if (reg[k] == 0 || (reg[k] == 1 && r.mu == 0))
        {
            f(0) = yn;
            B(0, 0) = 1.0 / r.Rn;
            if (r.mu > 0)
                for (int a = 1; a < m; ++a)
                {
                    f(a) = -vc[k](a) / r.Rt;
                    B(a, a) = 1.0 / r.Rt;
                }
        }
        else if (reg[k] == 1)
        {
            const double muHat = r.mu * r.Rt / r.Rn, c = 1.0 / (1.0 + r.mu * muHat);
            double yts = 0; // slip . y_t
            for (int a = 1; a < m; ++a) yts += -slip[k](a) * vc[k](a) / r.Rt;
            const double gn = c * (yn + muHat * yts);
            Eigen::Vector3d e = slip[k] * r.mu; // d gn/d(-v_c) direction: (1, mu t)/R_n c
            e(0) = 1.0;
            f = gn * e;
            B = (c / r.Rn) * e * e.transpose();
        } // separation: no impulse, no curvature (the block kept: one pattern)
        f(0) -= r.coh;
        addJT(k, -f, g);
        addBlock(k, B);
    }
}

void NewtonSolve::initialRegions(std::vector<int>& reg, std::vector<Eigen::Vector3d>& slip) const
{
    regions(reg);
    slip.assign(NC, Eigen::Vector3d::Zero());
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        Eigen::Vector3d f = warmImpulse(k);
        f(0) += r.coh; // the cone's impulse gamma
        const double ft = std::hypot(f(1), f(2));
        if (f(0) > 0)
        {
            if (r.mu == 0 || ft < (1 - 1e-6) * r.mu * f(0))
            {
                reg[k] = 0;
                continue;
            }
            reg[k] = 1;
            slip[k] = Eigen::Vector3d(0, f(1) / ft, f(2) / ft);
        }
        else if (reg[k] == 1)
            slip[k] = Eigen::Vector3d(0, -vc[k](1), -vc[k](2)).normalized();
    }
}

Eigen::Vector3d NewtonSolve::warmImpulse(int k) const
{
    const SolverContact& c = I.rows[k];
    const Vec3 P = c.rn * c.n + c.rt;
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    for (int a = 0; a < m; ++a) f(a) = P.dot(R[k].e[a]);
    return f;
}

int NewtonSolve::updateRegions(std::vector<int>& reg, std::vector<Eigen::Vector3d>& slip) const
{
    int changes = 0;
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        const double yn = -(vc[k](0) - r.vhatN) / r.Rn;
        const Eigen::Vector3d yt(0, -vc[k](1) / r.Rt, -vc[k](2) / r.Rt);
        const double yr = yt.norm();
        const double muHat = r.mu * r.Rt / r.Rn;
        int now = reg[k];
        if (!(yn > -muHat * yr))
            now = 2;
        else if (reg[k] == 1)
        {
            const double yts = slip[k].dot(yt);
            if (yts <= r.mu * yn)
                now = 0;
            else if (m == 3)
                slip[k] = yt / yr;
        }
        else if (r.mu > 0 && yr > r.mu * yn)
        {
            now = 1;
            slip[k] = yt / yr;
        }
        else
            now = 0;
        changes += now != reg[k];
        reg[k] = now;
    }
    return changes;
}

void NewtonSolve::startActiveSet(ActiveSet& A) const
{
    initialRegions(A.reg, A.slip);
    A.bestV = v;
    A.bestCost = cost;
    A.recentCosts.fill(-1.0);
    A.steps = 0;
}

bool NewtonSolve::activeSetStep(ActiveSet& A, double tol)
{
    regionModel(A.reg, A.slip, A.g);
    linearSolve(A.g);
    ++A.steps;
    v += dv;
    evaluate();
    const int changes = updateRegions(A.reg, A.slip);
    if (cost < A.bestCost)
    {
        A.bestCost = cost;
        A.bestV = v;
    }
    bool cycle = false; // the cost of one of the last iterates again: the regions cycle
    for (double c : A.recentCosts) cycle = cycle || std::abs(c - cost) <= 1e-12 * std::abs(cost);
    A.recentCosts[A.steps % A.recentCosts.size()] = cost;
    if ((changes == 0 && optimal(tol)) || !(changes == 0 || cycle || A.steps >= maxActiveSetSteps))
        return true;
    if (v != A.bestV)
    {
        v = A.bestV;
        evaluate();
    }
    return false;
}

} // namespace newton
} // namespace nscd
