// SPDX-License-Identifier: GPL-3.0-or-later
// APGD contact solve (System::Settings::Method::APGD): Nesterov-accelerated
// projected gradient with adaptive step and restart, Mazhar, Heyn, Negrut &
// Tasora, "Using Nesterov's method to accelerate multibody dynamics with
// friction and contact", ACM TOG 34(3) 32, 2015 (Algorithm 1), on the
// Signorini-Coulomb problem of the step:
//   g(r) = W r + b + mu |u_t(r)| e_n     (u = W r + b: contact velocities,
//                                         b: free velocity + gap term),
//   r <- Proj_K(y - t D^-1 g(y)),        K: the cones |r_t| <= mu (r_n + coh),
//                                         -coh <= r_n <= cap,
// with D = diag(W_nn) (Jacobi preconditioning: the same step for contacts of
// different stiffness). The normal shift mu |u_t| (De Saxce & Feng 1998,
// bipotential) makes the fixed points the Coulomb solutions instead of the
// cone complementarity ones of the paper, which let sliding contacts
// separate at mu |u_t|. The step size test of the paper,
// f(x) <= f(y) + g.(x - y) + L/2 |x - y|_D^2 for the quadratic f, reduces
// to d.W d <= L |d|_D^2 with d = x - y, whatever the (frozen) shift.
// Body velocities are kept for every iterate (W r = H M^-1 H^T r is applied
// through the bodies, as in the Gauss-Seidel): v(r) = v(r_0) + M^-1 H^T (r - r_0).
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

namespace
{
using Impulse = System::Impl::Impulse;
using Velocity = System::Impl::Velocity;

/// Relative velocity at contact c for body velocities V: du (global).
inline Vec3 relative(const SolverContact& c, const Body* B, const Velocity* V)
{
    const Velocity& a = V[c.i];
    const Velocity& b = V[c.j];
    return a.v - b.v - (B[c.i].r * a.w + B[c.j].r * b.w).cross(c.n);
}

/// Euclidean projection onto the contact's admissible set.
inline void project(const SolverContact& c, Impulse& r)
{
    if (c.mu == 0.0)
    {
        r.n = std::min(c.cap, std::max(-c.coh, r.n));
        r.t.setZero();
        return;
    }
    const double a = r.n + c.coh;
    const double s = r.t.norm();
    if (s <= c.mu * a)
    { /* inside the cone */
    }
    else if (c.mu * s <= -a)
    {
        r.n = -c.coh;
        r.t.setZero();
    }
    else
    {
        const double an = (a + c.mu * s) / (1 + c.mu * c.mu);
        r.n = an - c.coh;
        r.t *= c.mu * an / s;
    }
    if (r.n > c.cap)
    {
        r.n = c.cap;
        r.t.setZero();
    }
}
} // namespace

// APGD: residual (localResidual2) of impulses R at body velocities V.
double System::Impl::apgdResidual(const std::vector<Impulse>& R, const std::vector<Velocity>& V,
                                  double dt) const
{
    const Body* B = body.data();
    double res = 0;
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
        SolverContact c = rows[k];
        c.rn = R[k].n;
        const Body A{V[c.i].v, V[c.i].w, 0, 0, B[c.i].r}, Bb{V[c.j].v, V[c.j].w, 0, 0, B[c.j].r};
        res = std::max(res, localResidual2(c, R[k].t, A, Bb, dt));
    }
    return res;
}

// APGD: scratch sized, x_0 and its velocities from the (warm-started) rows and bodies.
void System::Impl::apgdStart()
{
    const std::size_t NC = rows.size(), NB = body.size();
    apgdX.resize(NC);
    apgdXn.resize(NC);
    apgdY.resize(NC);
    apgdG.resize(NC);
    apgdBest.resize(NC);
    apgdVX.resize(NB);
    apgdVXn.resize(NB);
    apgdVY.resize(NB);
    apgdVD.resize(NB);
    apgdVBest.resize(NB);
    for (std::size_t k = 0; k < NC; ++k) apgdX[k] = {rows[k].rn, rows[k].rt};
    for (std::size_t b = 0; b < NB; ++b) apgdVX[b] = {body[b].v, body[b].w};
}

// APGD: gradient at y, contact velocities with De Saxce's normal shift.
void System::Impl::apgdGradient()
{
    const Body* B = body.data();
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
        const SolverContact& c = rows[k];
        const Vec3 du = relative(c, B, apgdVY.data());
        const double un = du.dot(c.n);
        const Vec3 ut = du - un * c.n;
        apgdG[k] = {un + c.bias + c.mu * ut.norm(), ut};
    }
}

// APGD: projected step from y, step size by the quadratic upper bound (L doubled until it holds).
void System::Impl::apgdProjectedStep(double& L)
{
    const int NC = int(rows.size());
    const int NB = int(body.size());
    const Body* B = body.data();
    for (int tries = 0; tries < 60; ++tries)
    {
        const double t = 1.0 / L;
        for (int k = 0; k < NC; ++k)
        {
            const SolverContact& c = rows[k];
            Impulse r{apgdY[k].n - t * c.iwnn * apgdG[k].n, apgdY[k].t - t * c.iwnn * apgdG[k].t};
            project(c, r);
            apgdXn[k] = r;
        }
        // velocity change of d = xn - y: M^-1 H^T d
        for (int b = 0; b < NB; ++b)
        {
            apgdVD[b].v.setZero();
            apgdVD[b].w.setZero();
        }
        double dDd = 0;
        for (int k = 0; k < NC; ++k)
        {
            const SolverContact& c = rows[k];
            const double dn = apgdXn[k].n - apgdY[k].n;
            const Vec3 dtv = apgdXn[k].t - apgdY[k].t;
            dDd += c.wnn * (dn * dn + dtv.squaredNorm());
            const Vec3 P = dn * c.n + dtv;
            const Vec3 nxt = c.n.cross(dtv);
            apgdVD[c.i].v += B[c.i].im * P;
            apgdVD[c.i].w -= B[c.i].ii * B[c.i].r * nxt;
            apgdVD[c.j].v -= B[c.j].im * P;
            apgdVD[c.j].w -= B[c.j].ii * B[c.j].r * nxt;
        }
        double dWd = 0;
        for (int k = 0; k < NC; ++k)
        {
            const SolverContact& c = rows[k];
            const Vec3 du = relative(c, B, apgdVD.data());
            dWd += (apgdXn[k].n - apgdY[k].n) * du.dot(c.n) + (apgdXn[k].t - apgdY[k].t).dot(du);
        }
        if (dWd <= L * dDd * (1 + 1e-12) || dDd == 0) break;
        L *= 2;
    }
    for (int b = 0; b < NB; ++b) apgdVXn[b] = {apgdVY[b].v + apgdVD[b].v, apgdVY[b].w + apgdVD[b].w};
}

// APGD: Nesterov momentum, restart when the step goes against the gradient.
void System::Impl::apgdMomentum(double& theta)
{
    const std::size_t NC = rows.size(), NB = body.size();
    const double thetaN = 0.5 * (-theta * theta + theta * std::sqrt(theta * theta + 4));
    const double beta = theta * (1 - theta) / (theta * theta + thetaN);
    double gdx = 0;
    for (std::size_t k = 0; k < NC; ++k)
        gdx += apgdG[k].n * (apgdXn[k].n - apgdX[k].n) + apgdG[k].t.dot(apgdXn[k].t - apgdX[k].t);
    if (gdx > 0)
    {
        apgdY = apgdXn;
        apgdVY = apgdVXn;
        theta = 1;
    }
    else
    {
        for (std::size_t k = 0; k < NC; ++k)
            apgdY[k] = {apgdXn[k].n + beta * (apgdXn[k].n - apgdX[k].n),
                        apgdXn[k].t + beta * (apgdXn[k].t - apgdX[k].t)};
        for (std::size_t b = 0; b < NB; ++b)
            apgdVY[b] = {apgdVXn[b].v + beta * (apgdVXn[b].v - apgdVX[b].v),
                         apgdVXn[b].w + beta * (apgdVXn[b].w - apgdVX[b].w)};
        theta = thetaN;
    }
    std::swap(apgdX, apgdXn);
    std::swap(apgdVX, apgdVXn);
}

// APGD: the best iterate (smallest residual) into the rows and bodies.
void System::Impl::apgdKeepBest(double dt)
{
    const Body* B = body.data();
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
        SolverContact& c = rows[k];
        c.rn = apgdBest[k].n;
        c.rt = apgdBest[k].t;
        c.change = std::sqrt(localResidual2(c, c.rt, Body{apgdVBest[c.i].v, apgdVBest[c.i].w, 0, 0, B[c.i].r},
                                            Body{apgdVBest[c.j].v, apgdVBest[c.j].w, 0, 0, B[c.j].r}, dt));
    }
    for (std::size_t b = 0; b < body.size(); ++b)
    {
        body[b].v = apgdVBest[b].v;
        body[b].w = apgdVBest[b].w;
    }
}

void System::Impl::solveAPGD(double dt, StepReport& rep)
{
    const int NC = int(rows.size());
    const double dmin = 2 * rMin();
    const double tol2 = std::pow(settings.tolerance * dmin, 2);
    const bool hist = settings.residualHistory;
    rep.contacts = NC;
    apgdStart();
    auto toDmin = [&](double r2) { return dmin > 0 ? std::sqrt(r2) / dmin : 0.0; };
    double res = apgdResidual(apgdX, apgdVX, dt);
    if (hist) rep.residualHistory.push_back(toDmin(res));
    apgdBest = apgdX;
    apgdVBest = apgdVX;
    double resBest = res;
    apgdY = apgdX;
    apgdVY = apgdVX;
    double theta = 1, L = 1;
    int it = 0;
    const int maxIt = settings.maxIterations;
    while (resBest > tol2 && it < maxIt)
    {
        ++it;
        apgdGradient();
        apgdProjectedStep(L);
        res = apgdResidual(apgdXn, apgdVXn, dt);
        if (hist) rep.residualHistory.push_back(toDmin(std::min(res, resBest)));
        if (res < resBest)
        {
            resBest = res;
            apgdBest = apgdXn;
            apgdVBest = apgdVXn;
            if (res <= tol2) break;
        }
        apgdMomentum(theta);
        L *= 0.9;
    }
    apgdKeepBest(dt);
    rep.localSolves = long(it) * NC;
    rep.sweeps = it;
    rep.residual = toDmin(resBest);
    rep.converged = resBest <= tol2;
}

} // namespace nscd
