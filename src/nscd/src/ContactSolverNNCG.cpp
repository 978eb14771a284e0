// SPDX-License-Identifier: GPL-3.0-or-later
// NNCG contact solve (System::Settings::Method::NNCG): nonsmooth nonlinear
// conjugate gradient, Silcowitz, Niebe & Erleben, "A nonsmooth nonlinear
// conjugate gradient method for interactive contact force problems", The
// Visual Computer 26, 893-901, 2010 (Algorithm 2 there). Each iteration is
// one full projected Gauss-Seidel sweep x_{k+1} = PGS(x_k) (the local solve
// of LocalSolve.H, alternately forward and backward over the contact list:
// a symmetric Gauss-Seidel) whose step d_{k+1} = x_{k+1} - x_k plays the
// part of the negative gradient of a Fletcher-Reeves conjugate gradient:
//   beta = |d_{k+1}|^2 / |d_k|^2;   beta > 1: restart (p = 0);
//   otherwise x_{k+1} += beta p_k,  p_{k+1} = beta p_k + d_{k+1}.
// The momentum step is applied to the bodies as an impulse (v += M^-1 H^T
// beta p), so velocities and impulses stay consistent as in the plain
// Gauss-Seidel; it may leave the admissible cones, which the next sweep's
// local solves project back (the solve only stops after a sweep).
// |d|^2 is measured with the residual's metric, sum_k |W_kk d_k|^2 k_k^2, so
// that contacts of different stiffness weigh as in the stopping test.
// Stopping test: the common residual of every method (ContactSolver.cpp),
// max_k |W_kk (r_k* - r_k)| dt <= tolerance d_min, checked after a sweep
// whose largest local change is below it.
#include "LocalSolve.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

void System::Impl::solveNNCG(double dt, StepReport& rep)
{
    const bool twoD = dim == 2;
    const bool anitescu = settings.frictionLaw == Settings::FrictionLaw::Anitescu;
    const double dmin = 2 * rMin();
    const int NC = int(rows.size());
    const bool hist = settings.residualHistory;
    auto toDmin = [&](double r2) { return dmin > 0 ? std::sqrt(r2) / dmin : 0.0; };
    SolverContact* cs = rows.data();
    Body* const B = body.data();
    const double dt2 = dt * dt;
    const double xi = settings.tolerance * dmin, xi2 = xi * xi;
    if (twoD)
        for (int k = 0; k < NC; ++k) cs[k].rts = cs[k].rt.dot(Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0));
    // impulses of the previous iterate and the conjugate direction p, per
    // contact (2D: the tangential component in t.x())
    nncgPrevious.resize(NC);
    nncgDirection.assign(NC, Impulse{0.0, Vec3::Zero()});
    Impulse* prev = nncgPrevious.data();
    Impulse* p = nncgDirection.data();
    auto tangent = [&](const SolverContact& c) { return twoD ? Vec3(c.rts, 0, 0) : c.rt; };
    double res2 = residualPass(dt, twoD);
    if (hist) rep.residualHistory.push_back(toDmin(res2));
    int it = 0;
    bool converged = res2 < xi2;
    bool forward = true;
    double d2Previous = 0;
    while (!converged && it < settings.maxIterations)
    {
        // x_{k+1} = PGS(x_k): one full symmetric-order sweep, every update applied
        double maxChange = 0;
        for (int s = 0; s < NC; ++s)
        {
            const int k = forward ? s : NC - 1 - s;
            SolverContact& c = cs[k];
            prev[k].n = c.rn;
            prev[k].t = tangent(c);
            if (twoD)
                local::update2D(c, B[c.i], B[c.j], dt2, 0.0, 1.0, anitescu);
            else
                local::update3D(c, B[c.i], B[c.j], dt2, 0.0, 1.0, anitescu);
            maxChange = std::max(maxChange, c.change);
        }
        forward = !forward;
        ++it;
        if (maxChange < xi2)
        {
            res2 = residualPass(dt, twoD);
            if (hist) rep.residualHistory.push_back(toDmin(res2));
            if (res2 < xi2)
            {
                converged = true;
                break;
            }
        }
        // d_{k+1} = x_{k+1} - x_k and its norm in the residual metric
        double d2 = 0;
        for (int k = 0; k < NC; ++k)
        {
            const SolverContact& c = cs[k];
            const double dn = c.rn - prev[k].n;
            const Vec3 dtv = tangent(c) - prev[k].t;
            d2 += (c.wnn * c.wnn * dn * dn + c.wtt * c.wtt * dtv.squaredNorm()) * c.residualWeight2;
            prev[k].n = dn; // prev now holds d_{k+1}
            prev[k].t = dtv;
        }
        const double beta = it > 1 && d2Previous > 0 ? d2 / d2Previous : 0.0;
        d2Previous = d2;
        // no momentum after the last sweep: the impulses returned are projected
        if (it == settings.maxIterations) break;
        if (beta > 1.0 || beta == 0.0)
        {
            // (re)start: p = d_{k+1} (beta > 1 is the restart of Algorithm 2)
            for (int k = 0; k < NC; ++k) p[k] = beta > 1.0 ? Impulse{0.0, Vec3::Zero()} : prev[k];
        }
        else
        {
            // x_{k+1} += beta p_k (impulses and body velocities); p_{k+1} = beta p_k + d_{k+1}
            for (int k = 0; k < NC; ++k)
            {
                SolverContact& c = cs[k];
                const double dn = beta * p[k].n;
                const Vec3 dtv = beta * p[k].t;
                c.rn += dn;
                if (twoD)
                {
                    c.rts += dtv.x();
                    local::applyImpulse2D(c, B[c.i], B[c.j], dn, dtv.x());
                }
                else
                {
                    c.rt += dtv;
                    local::applyImpulse3D(c, B[c.i], B[c.j], dn, dtv);
                }
                p[k].n = dn + prev[k].n;
                p[k].t = dtv + prev[k].t;
            }
        }
        if (hist && !(maxChange < xi2)) rep.residualHistory.push_back(toDmin(residualPass(dt, twoD)));
    }
    if (!converged)
    {
        res2 = residualPass(dt, twoD);
        if (hist) rep.residualHistory.push_back(toDmin(res2));
    }
    if (twoD)
        for (int k = 0; k < NC; ++k) cs[k].rt = cs[k].rts * Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0);
    for (int k = 0; k < NC; ++k) cs[k].change = std::sqrt(cs[k].change);
    rep.method = int(Settings::Method::NNCG);
    rep.contacts = NC;
    rep.localSolves = long(it) * long(NC);
    rep.sweeps = it;
    rep.residual = toDmin(res2);
    rep.converged = converged;
}

} // namespace nscd
