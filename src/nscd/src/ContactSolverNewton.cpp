// SPDX-License-Identifier: GPL-3.0-or-later
// Newton contact solve for compliant contacts (System::Settings::Method::Newton):
// the primal, unconstrained convex formulation of compliant contact of
// A. M. Castro, F. N. Permenter & X. Han, "An unconstrained convex
// formulation of compliant contact", IEEE Trans. Robotics 39(2), 2023
// (Drake's SAP; MuJoCo's Newton solver, E. Todorov, "Convex and analytically-
// invertible dynamics with contacts and constraints", ICRA 2014, is of the
// same family). Written from the paper; no code copied.
//
// Unknowns: the velocities v of the movable bodies (grains: translation,
// and rotation unless locked; 2D: v_x, v_y, w_z; 3D: v, w), size nv. Cost
//   l(v) = 1/2 (v - v*)^T M (v - v*) + sum_k [l_k(J_k v + c_k) + coh_k (J_k v + c_k)_n]
// M = diag(m + dt c_drag, I) (the NLGS's effective masses), v* the free
// velocities (eq. 2.11, the warm start's impulses removed), J_k the contact
// Jacobian in the contact's frame (n, t1[, t2]) and c_k the part of the
// contact velocity from bodies that are not unknowns (walls, fixed grains,
// locked rotations), l_k the cost of the regularised cone projection
// (NewtonCone.H) with R_n = eps (the compliant law's regularisation,
// ContactLaws.H), R_t = sigma R_n, vhat_n = -(bias - eps coh) (the law's
// gap term; cohesion shifts the cone to r_n >= -coh, r~ = r + coh e_n).
// grad l = M (v - v*) - sum_k J_k^T (gamma_k - coh_k e_n), so at the minimum
// M (v - v*) = J^T r with r = gamma - coh e_n: momentum balance with the
// compliant law's impulses (Castro et al., eq. 18-20 and Theorem 1).
// Each iteration is one linear solve with a matrix M + sum_k J_k^T B_k J_k
// (Eigen SparseMatrix, lower triangle, one pattern per step, filled in
// place; kept with its LDLT ordering for the next step when the rows touch
// the same unknowns), by SimplicialLDLT or incomplete-Cholesky CG
// (Settings::newtonLinearSolver). Two stages:
//  1. active-set steps (a primal-dual active-set method in the manner of
//     Hintermueller, Ito & Kunisch, SIAM J. Optim. 13(3), 2002, and of
//     Hueeber, Stadler & Wohlmuth, SIAM J. Sci. Comput. 30(2), 2008, for
//     Coulomb friction): each row keeps a region (stiction, sliding along
//     a direction, separation), first the warm start's (the previous
//     step's impulse), then updated from the model's solution: the step
//     goes to the minimiser of the quadratic model of l in which each row
//     keeps its region (B_k its curvature there), the full step;
//  2. when the regions settle without optimality, cycle or reach
//     maxActiveSetSteps: Newton's steps on l from the best iterate (B_k =
//     G_k at v, H dv = -grad l) with the exact line search on l along dv
//     (a safeguarded Newton-bisection on dl/dalpha; l is convex).
// Why not Newton on l alone, as the paper: a row's region at v is decided
// within mu R_t gamma_n of tangential velocity (R_t = sigma R_n, 6e-9 m/s
// a layer on the landing column with beta 2e-3, sigma 1e-3), far below
// the error of any iterate, so most loaded rows start in the wrong region;
// a wrong sliding row has no curvature along its slip (in 2D), Newton's
// step overshoots its stiction band by ~1/(mu^2 sigma), and the exact line
// search stops at the first such kink: a few rows corrected per iteration,
// an iteration count that grows with the rows (docs/validation/
// contactCompliance.md, "The Newton solver"). The regions carried by the
// active-set steps do not depend on the iterate's tangential noise.
// Stop on SAP's relative optimality test (Settings::newtonTolerance).
// At the end the bodies get v* + M^-1 J^T r(v) (momentum exactly
// consistent with the rows' impulses, as in the Gauss-Seidel methods) and
// the rows r(v); StepReport::residual is the common residual of every
// method (ContactSolver.cpp; it also sees the tangential creep R_t r_t).
// Files: this one (the unknowns, the rows, the cost, the line search and
// the driver), ContactSolverNewtonLinear.cpp (the matrix, its pattern cache
// and the linear solve), ContactSolverNewtonActiveSet.cpp (the region model
// and the active-set stage); their shared state: ContactSolverNewtonImpl.H.
#include "ContactSolverNewtonImpl.H"

#include <algorithm>
#include <cmath>

namespace nscd
{
namespace newton
{

void NewtonSolve::numberUnknowns(Eigen::VectorXd& x0)
{
    const int NB = int(I.body.size());
    tDof.assign(NB, -1);
    rDof.assign(NB, -1);
    nv = 0;
    for (int b = 0; b < NB; ++b)
    {
        if (!(I.body[b].im > 0)) continue;
        tDof[b] = nv;
        nv += nt();
        if (I.body[b].ii > 0)
        {
            rDof[b] = nv;
            nv += nr();
        }
    }
    mass.resize(nv);
    x0.resize(nv);
    for (int b = 0; b < NB; ++b)
    {
        const Body& B = I.body[b];
        if (tDof[b] >= 0)
            for (int a = 0; a < nt(); ++a)
            {
                mass(tDof[b] + a) = 1.0 / B.im;
                x0(tDof[b] + a) = B.v(a);
            }
        if (rDof[b] >= 0)
        {
            if (I.dim == 2)
            {
                mass(rDof[b]) = 1.0 / B.ii;
                x0(rDof[b]) = B.w.z();
            }
            else
                for (int a = 0; a < 3; ++a)
                {
                    mass(rDof[b] + a) = 1.0 / B.ii;
                    x0(rDof[b] + a) = B.w(a);
                }
        }
    }
}

void NewtonSolve::addSide(NewtonRow& r, int b, double sign, const Vec3& n)
{
    const Body& B = I.body[b];
    // contact velocity du = v_A - v_B - (r_A w_A + r_B w_B) x n
    // (eq. 2.14-2.18): along e, sign v . e - r w . (n x e), the
    // rotation's sign the same for A and B (their contact points are
    // at -r_A n and +r_B n)
    Vec3 nxe[3];
    for (int a = 0; a < m; ++a) nxe[a] = n.cross(r.e[a]);
    const Vec3 vFix = tDof[b] >= 0 ? Vec3::Zero() : B.v;
    const Vec3 wFix = rDof[b] >= 0 ? Vec3::Zero() : B.w;
    for (int a = 0; a < m; ++a) r.c0(a) += sign * vFix.dot(r.e[a]) - B.r * wFix.dot(nxe[a]);
    if (tDof[b] >= 0)
        for (int d = 0; d < nt(); ++d)
        {
            const int k = r.ncol++;
            r.col[k] = tDof[b] + d;
            for (int a = 0; a < m; ++a) r.J[a][k] = sign * r.e[a](d);
        }
    if (rDof[b] >= 0)
        for (int d = 0; d < nr(); ++d)
        {
            const int k = r.ncol++;
            const int comp = I.dim == 2 ? 2 : d;
            r.col[k] = rDof[b] + d;
            for (int a = 0; a < m; ++a) r.J[a][k] = -B.r * nxe[a](comp);
        }
}

void NewtonSolve::buildRows(double sigma)
{
    R.resize(NC);
    for (int k = 0; k < NC; ++k)
    {
        const SolverContact& s = I.rows[k];
        NewtonRow& r = R[k];
        const Vec3& n = s.n;
        r.e[0] = n;
        if (I.dim == 2)
        {
            r.e[1] = Vec3(-n.y(), n.x(), 0.0);
            r.e[2].setZero();
        }
        else
        {
            // tangents: t1 orthogonal to n and to its smallest component's axis
            const Vec3 a = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
            r.e[1] = (a - a.dot(n) * n).normalized();
            r.e[2] = n.cross(r.e[1]);
        }
        r.ncol = 0;
        r.c0.setZero();
        addSide(r, s.i, 1.0, n);
        addSide(r, s.j, -1.0, n);
        // the compliant law's eps: iwnn = 1/(W_nn + eps) (prepareContacts)
        const double eps = s.iwnn > 0 ? 1.0 / s.iwnn - s.wnn : 0.0;
        r.skip = r.ncol == 0; // no movable body (e.g. a fixed grain on a wall): no impulse
        if (r.skip) continue;
        if (!(eps > 1e-12 * s.wnn) || std::isfinite(s.cap))
            throw InputError("nscd::System::step: the Newton contact solver met a hard (zero-compliance) "
                             "or capped contact (bodies "
                             + std::to_string(s.i) + ", " + std::to_string(s.j)
                             + "); every contact needs a compliance");
        r.Rn = eps;
        r.Rt = sigma * eps;
        r.mu = s.mu;
        r.coh = s.coh;
        r.vhatN = -(s.bias - eps * s.coh);
    }
}

void NewtonSolve::evaluate()
{
    const Eigen::VectorXd dvStar = v - vStar;
    cost = 0.5 * dvStar.dot(mass.cwiseProduct(dvStar));
    Eigen::VectorXd jc = Eigen::VectorXd::Zero(nv);
    vc.resize(NC);
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        vc[k] = contactVelocity(k, v, true);
        if (r.skip) continue;
        const ConeProjection p = project(vc[k], r.vhatN, r.Rn, r.Rt, r.mu, false);
        cost += p.cost + r.coh * vc[k](0);
        addJT(k, impulse(k, p), jc);
    }
    grad = mass.cwiseProduct(dvStar) - jc;
    const Eigen::VectorXd D = mass.cwiseSqrt().cwiseInverse();
    gNorm = grad.cwiseProduct(D).norm();
    pNorm = mass.cwiseProduct(v).cwiseProduct(D).norm();
    jNorm = jc.cwiseProduct(D).norm();
}

void NewtonSolve::lineDerivatives(double alpha, double a, double b, double& d1, double& d2) const
{
    d1 = b + alpha * a;
    d2 = a;
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        const Eigen::Vector3d u = vc[k] + alpha * wc[k];
        const ConeProjection p = project(u, r.vhatN, r.Rn, r.Rt, r.mu, true);
        d1 += -p.gamma.dot(wc[k]) + r.coh * wc[k](0);
        d2 += wc[k].dot(p.G * wc[k]);
    }
}

double NewtonSolve::lineSearch(int& evals)
{
    constexpr double alphaMax = 1.5;
    wc.resize(NC);
    for (int k = 0; k < NC; ++k) wc[k] = contactVelocity(k, dv, false);
    const double a = dv.dot(mass.cwiseProduct(dv));
    const double b = dv.dot(mass.cwiseProduct(v - vStar));
    double d1, d2;
    lineDerivatives(0.0, a, b, d1, d2);
    ++evals;
    const double d10 = d1;
    if (!(d10 < 0)) return 0.0; // not a descent direction (round-off): stop
    double lo = 0, hi = alphaMax;
    lineDerivatives(hi, a, b, d1, d2);
    ++evals;
    if (d1 <= 0) return hi;
    double alpha = 1.0;
    for (int it = 0; it < 50; ++it)
    {
        lineDerivatives(alpha, a, b, d1, d2);
        ++evals;
        if (std::abs(d1) <= 1e-10 * std::abs(d10)) break;
        if (d1 < 0)
            lo = alpha;
        else
            hi = alpha;
        if (hi - lo <= 1e-12 * hi) break;
        const double next = d2 > 0 ? alpha - d1 / d2 : -1.0;
        alpha = next > lo && next < hi ? next : 0.5 * (lo + hi);
    }
    return alpha;
}

void NewtonSolve::start(const System::Settings& settings)
{
    Eigen::VectorXd x0;
    numberUnknowns(x0);
    buildRows(settings.tangentialRegularisation);
    // free velocities: the warm-started bodies minus the rows' impulses
    {
        Eigen::VectorXd jr = Eigen::VectorXd::Zero(nv);
        for (int k = 0; k < NC; ++k) addJT(k, warmImpulse(k), jr);
        vStar = x0 - jr.cwiseQuotient(mass);
    }
    v = x0;
    buildPattern();
    useCg = settings.newtonLinearSolver == System::Settings::NewtonLinearSolver::ConjugateGradient;
}

bool NewtonSolve::newtonStep(int& evals, bool& stalled)
{
    const double before = cost;
    hessian();
    linearSolve(grad);
    const double alpha = lineSearch(evals);
    if (!(alpha > 0)) return false; // no descent left (round-off): converged only by the test
    v += alpha * dv;
    evaluate();
    // round-off floor of the cost: stop; converged only by the test
    stalled = std::abs(before - cost) <= costStall * std::abs(cost);
    return !stalled;
}

void NewtonSolve::finish(bool converged)
{
    // the rows' impulses r(v) and the bodies' velocities v* + M^-1 J^T r
    Eigen::VectorXd jr = Eigen::VectorXd::Zero(nv);
    const bool twoD = I.dim == 2;
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        SolverContact& c = I.rows[k];
        if (r.skip)
        {
            c.rn = c.rts = 0;
            c.rt.setZero();
            continue;
        }
        const ConeProjection p = project(contactVelocity(k, v, true), r.vhatN, r.Rn, r.Rt, r.mu, false);
        const Eigen::Vector3d f = impulse(k, p);
        addJT(k, f, jr);
        c.rn = f(0);
        c.rt = f(1) * r.e[1] + (twoD ? Vec3::Zero() : Vec3(f(2) * r.e[2]));
        if (twoD) c.rts = f(1);
    }
    // converged: v* + M^-1 J^T r, momentum exactly consistent with the rows
    // (it differs from v by M^-1 grad l, within the tolerance); not
    // converged: the iterate v itself (its cost is below the warm start's),
    // since r(v) amplifies a velocity error e by 1/R_t (e/R_t: 5e5 e/W_nn
    // with beta 2e-3 and sigma 1e-3), which v* + M^-1 J^T r would turn into
    // velocities (measured: 8e4 m/s after a capped step of the landing column)
    const Eigen::VectorXd vEnd = converged ? Eigen::VectorXd(vStar + jr.cwiseQuotient(mass)) : v;
    const int NB = int(I.body.size());
    for (int b = 0; b < NB; ++b)
    {
        Body& B = I.body[b];
        if (tDof[b] >= 0)
            for (int a = 0; a < nt(); ++a) B.v(a) = vEnd(tDof[b] + a);
        if (rDof[b] >= 0)
        {
            if (twoD)
                B.w.z() = vEnd(rDof[b]);
            else
                for (int a = 0; a < 3; ++a) B.w(a) = vEnd(rDof[b] + a);
        }
    }
}

} // namespace newton

void System::Impl::solveNewton(double dt, StepReport& rep)
{
    newton::NewtonSolve S(*this, dt);
    const int NC = S.NC;
    const bool hist = settings.residualHistory;
    const double dmin = 2 * rMin();
    rep.method = int(Settings::Method::Newton);
    rep.contacts = NC;
    S.start(settings);
    const double tol = settings.newtonTolerance;
    const int maxIt = std::min(settings.maxIterations, newton::maxNewtonIterations);
    int it = 0, evals = 0;
    bool converged = false;
    S.evaluate();
    // Stage 1, active-set steps: the rows' regions are carried from step to
    // step (the warm start's) and from iteration to iteration (updateRegions),
    // not read off the iterate (see the head of this file). Each step goes to the
    // minimiser of the quadratic model with those regions (one linear solve),
    // the full step whatever the cost does there (the best iterate is kept).
    // Stage 2, when the regions settle without optimality, cycle or reach
    // maxActiveSetSteps: Newton's steps on l from the best iterate, with the
    // exact line search (convergent: l is convex and decreases at each step).
    newton::ActiveSet A;
    S.startActiveSet(A);
    bool activeSet = true;
    while (true)
    {
        if (hist) rep.residualHistory.push_back(S.optimality());
        if (S.nv == 0 || S.optimal(tol))
        {
            converged = true;
            break;
        }
        if (it >= maxIt) break;
        ++it;
        if (activeSet)
        {
            activeSet = S.activeSetStep(A, tol);
            continue;
        }
        bool stalled = false;
        if (S.newtonStep(evals, stalled)) continue;
        if (stalled)
        {
            if (hist) rep.residualHistory.push_back(S.optimality());
            converged = S.optimal(tol);
        }
        break;
    }
    S.finish(converged);
    // the common residual (ContactSolver.cpp), row by row into change
    double res2 = 0;
    for (SolverContact& c : rows)
    {
        const double r2 = localResidual2(c, c.rt, body[c.i], body[c.j], dt);
        res2 = std::max(res2, r2);
        c.change = std::sqrt(r2);
    }
    rep.sweeps = it;
    rep.localSolves = long(evals + it + 1) * long(NC);
    rep.linearIterations = S.cgIterations;
    rep.residual = dmin > 0 ? std::sqrt(res2) / dmin : 0.0;
    rep.converged = converged;
}

} // namespace nscd
