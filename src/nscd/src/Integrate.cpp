// SPDX-License-Identifier: GPL-3.0-or-later
// The end of a step (System::step, Step.cpp): the energy limit of a capped
// solve, the drag impulses of the step, and the integration of velocities,
// positions (exact rotation), walls and droplets.
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

namespace
{
/// Exact rotation update q <- exp(w dt / 2) q (w in the global frame),
/// renormalised: dq = (cos h, sin h w/|w|), h = |w| dt/2. Below h = 5e-3
/// (every grain of a bed at rest) sin h and cos h are their Taylor series
/// to h^5 and h^6, equal to them to round-off (the next terms are below
/// 3e-18 of them), which saves the library calls.
Eigen::Quaterniond rotate(const Eigen::Quaterniond& q, const Vec3& w, double dt)
{
    const double wn = w.norm();
    const double h = 0.5 * wn * dt;
    if (h == 0.0) return q;
    double s, c;
    if (h < 5e-3)
    {
        const double h2 = h * h;
        s = h * (1 - h2 / 6 * (1 - h2 / 20));
        c = 1 - h2 / 2 * (1 - h2 / 12 * (1 - h2 / 30));
    }
    else
    {
        s = std::sin(h);
        c = std::cos(h);
    }
    const Vec3 u = (s / wn) * w;
    const Eigen::Quaterniond dq(c, u.x(), u.y(), u.z());
    Eigen::Quaterniond r = dq * q;
    r.normalize();
    return r;
}
} // namespace

// ---- velocities and positions (eq. 2.9, 5.4), exact rotation ----
void System::Impl::integrate(double dt, int NC0)
{
    const int N = int(x.size());
    const int NW = int(walls.size());
    const int ND = int(droplets.size());
    accumulateDragImpulses(dt);
    for (int i = 0; i < N; ++i) // by grain (see freeVelocities)
    {
        const int s = slotOf[i];
        const Body& B = body[s];
        v[i] = B.v;
        w[i] = B.w;
        x[i] += dt * (relaxPositionVelocity.empty() ? B.v : relaxPositionVelocity[s]);
        packed[s].x = x[i]; // end-of-step centres by slot (storeImpulses' gaps)
        q[i] = rotate(q[i], B.w, dt);
    }
    for (int k = 0; k < NW; ++k) walls[k].displacement += dt * walls[k].velocity;
    for (int k = 0; k < ND; ++k)
    {
        Droplet& D = droplets[k];
        if (D.mass > 0) D.velocity = body[N + NW + k].v;
        D.centre += dt * D.velocity;
    }
    for (int k = NC0; k < int(rows.size()); ++k) // impulse -r on the droplet (body B)
    {
        const SolverContact& c = rows[k];
        Droplet& D = droplets[c.j - N - NW];
        D.impulse -= c.rn * c.n;
        D.grainImpulse[order[c.i]] += c.rn;
    }
    time += dt;
}

// ---- a capped (unconverged) solve may not raise the kinetic energy ----
// For the dissipative law (inelastic Signorini with bias >= 0, Coulomb
// friction, static walls, no cohesion or droplet) the exact solution only
// removes energy from the free velocities, but a warm-started Gauss-Seidel
// stopped at maxIterations can leave impulses that add energy (a deep
// frictionless column: 40-fold in one step, docs/validation/dropletDigging.md:
// why no deep bed of these grains comes to rest). Then the contact impulses r are scaled to alpha r,
// alpha in [0, 1) the minimiser of the kinetic energy
//   E(alpha) = E_free + alpha b + alpha^2 a,
// b = sum v_free . M dv, a = |dv|_M^2 / 2, dv the velocity change of the
// solve, so E(alpha) <= E_free: alpha r stays in the Coulomb cone (it is a
// cone), and the step dissipates (a line search along the impulse of the
// solve, as an energy-based step rejection). The metric is the solve's
// (effective masses, implicit drag included). The positions of the step
// follow the solve's velocities (or the relax stage's), as in a split
// impulse: only the velocities kept are scaled. Converged steps are untouched.
void System::Impl::limitCappedEnergy(double dt, StepReport& rep)
{
    if (rep.converged || !droplets.empty() || anyCompliance()) return;
    for (const auto& W : walls)
        if (!W.velocity.isZero()) return;
    for (const SolverContact& c : rows)
        if (c.coh > 0) return;
    const int N = int(x.size());
    for (int i = 0; i < N; ++i)
        if (fix[i] && !(v[i].isZero() && w[i].isZero())) return;
    // free velocities again from the start-of-step state (v, w are kept until integrate)
    std::vector<Vec3>& vf = contactSum; // scratch (accumulateDragImpulses refills it)
    vf.resize(2 * std::size_t(N));
    double e0 = 0, a = 0, b = 0;
    for (int i = 0; i < N; ++i)
    {
        if (fix[i]) continue;
        const Body& B = body[slotOf[i]];
        Vec3 v0, w0;
        freeBodyVelocity(i, dt, B.ii, v0, w0);
        vf[2 * i] = v0;
        vf[2 * i + 1] = w0;
        const double m = 1.0 / B.im, J = B.ii > 0 ? 1.0 / B.ii : 0.0;
        const Vec3 dv = B.v - v0, dw = B.w - w0;
        e0 += 0.5 * (m * v0.squaredNorm() + J * w0.squaredNorm());
        b += m * v0.dot(dv) + J * w0.dot(dw);
        a += 0.5 * (m * dv.squaredNorm() + J * dw.squaredNorm());
    }
    if (!(a + b > 0)) return; // E(1) <= E_free: nothing to do
    const double alpha = b < 0 ? -b / (2 * a) : 0.0;
    // the grains still move with the solve's velocities in this step (as the
    // relax stage's positions: the overlaps the solve prevents stay
    // prevented); only the velocities they keep are scaled
    if (relaxPositionVelocity.empty()) holdPositionVelocities();
    for (int i = 0; i < N; ++i)
    {
        if (fix[i]) continue;
        Body& B = body[slotOf[i]];
        B.v = vf[2 * i] + alpha * (B.v - vf[2 * i]);
        B.w = vf[2 * i + 1] + alpha * (B.w - vf[2 * i + 1]);
    }
    for (SolverContact& c : rows)
    {
        c.rn *= alpha;
        c.rt *= alpha;
        c.rts *= alpha;
    }
    ++rep.energyLimited;
    rep.impulseScale = std::min(rep.impulseScale, alpha);
    rep.energyRaise = std::max(rep.energyRaise, e0 > 0 ? (a + b) / e0 : 0.0);
}

// Drag impulse dt c (u - v^+) of the step. v^+ = v_free + R/(m + dt c), R
// the grain's total contact impulse, so
//   dt c (u - v^+) = dt c (m (u - v_0) - R)/(m + dt c),  v_0 = v + dt (g + F/m),
// evaluated in this form: u - v^+ itself cancels to round-off when c dt/m is
// large (a grain locked to its fluid) and c would multiply that round-off.
void System::Impl::accumulateDragImpulses(double dt)
{
    const int N = int(x.size());
    bool any = false;
    for (int i = 0; i < N && !any; ++i) any = dragCoefficient[i] > 0 && !fix[i];
    if (!any) return;
    contactSum.assign(N, Vec3::Zero());
    for (const SolverContact& c : rows)
    {
        const Vec3 P = c.rn * c.n + c.rt;
        if (c.i < N) contactSum[c.i] += P;
        if (c.j < N) contactSum[c.j] -= P;
    }
    if (dragInterface) // interface grains: n (local contacts + interface impulse)
        for (const DragInterfaceTerm& t : *dragInterface)
        {
            Vec3& R = contactSum[slotOf[t.grain]];
            R = double(t.copies) * (R + t.impulse);
        }
    for (int s = 0; s < N; ++s) // contactSum by slot
    {
        const int i = order[s];
        const double c = dragCoefficient[i];
        if (!(c > 0) || fix[i]) continue;
        const Vec3 v0 = v[i] + dt * (g + force[i] / mass[i]);
        const Vec3& R = contactSum[s];
        Vec3 J = dt * c * (mass[i] * (dragVelocity[i] - v0) - R) / effectiveMass(i, dt);
        if (dim == 2) J.z() = 0;
        dragImpulse[i] += J;
    }
}

} // namespace nscd
