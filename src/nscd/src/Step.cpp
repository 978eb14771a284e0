// SPDX-License-Identifier: GPL-3.0-or-later
// System::step in named stages (the contact solve itself is in ContactSolver.cpp).
//
// Layout, in the manner of Box2D v3 (E. Catto, solver.c / contact_solver.c):
// the persistent contact records (Impl::contacts, struct Contact: bodies,
// normal, impulses, age) outlive the step; the solver works on scratch rows
// (Impl::rows, struct SolverContact) built from the detected contacts by
// prepareContacts and written back by storeImpulses.
//
//   validate -> freeVelocities -> [detect -> prepareContacts (+ warmStart of
//   each row) -> buildAdjacency -> solveContacts] (detectAndSolve: repeated
//   with larger reaches if a grain leaves its reach) -> integrate ->
//   storeImpulses -> heat
// The warm start and the adjacency counts are applied row by row inside
// prepareContacts (one pass over the rows instead of three: at 70,000 discs
// at rest the passes over the contact arrays are memory-bound).
#include "ContactLaws.H"
#include "SystemImpl.H"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace nscd
{

namespace
{
/// Re-detections of one step (detectAndSolve).
constexpr int maxRedetections = 4;

/// Largest residual weight k of a contact (SolverContact::residualWeight2)
constexpr double maxResidualWeight = 1e3;

/// prepareContacts prefetches the bodies of the row this far ahead
/// (the bodies are visited out of memory order; results unchanged).
constexpr int bodiesAhead = 8;

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

void System::Impl::checkSettings(const System::Settings& S, const char* where)
{
    if (!(S.tolerance > 0) || S.maxIterations < 1 || !(S.relaxation > 0 && S.relaxation < 2)
        || !(S.overlapSlop >= 0) || !(S.alertDistanceFactor >= 0) || !(S.alertMargin >= 0)
        || !(S.verletSkin >= 0 && std::isfinite(S.verletSkin)))
        throw InputError(
            std::string(where)
            + ": invalid settings (need tolerance > 0, maxIterations >= 1, "
              "0 < relaxation < 2, overlapSlop >= 0, alert factors >= 0, finite verletSkin >= 0)");
    const int m = int(S.method);
    if (m < 0 || m > int(System::Settings::Method::Newton))
        throw InputError(std::string(where) + ": invalid settings (unknown contact solver method "
                         + std::to_string(m) + "; methods: NLGS, OverRelaxedNLGS, APGD, NNCG, Newton)");
    if (S.method == System::Settings::Method::Newton)
    {
        if (!(S.newtonTolerance > 0) || !std::isfinite(S.newtonTolerance) || !(S.tangentialRegularisation > 0)
            || !std::isfinite(S.tangentialRegularisation))
            throw InputError(std::string(where)
                             + ": invalid settings (Newton needs newtonTolerance > 0 and "
                               "tangentialRegularisation > 0, both finite; got "
                             + std::to_string(S.newtonTolerance) + " and "
                             + std::to_string(S.tangentialRegularisation) + ")");
        const int ls = int(S.newtonLinearSolver);
        if (ls < 0 || ls > int(System::Settings::NewtonLinearSolver::ConjugateGradient))
            throw InputError(std::string(where) + ": invalid settings (unknown newtonLinearSolver "
                             + std::to_string(ls) + "; Cholesky, ConjugateGradient)");
    }
    const int cv = int(S.convergence);
    if (cv < 0 || cv > int(System::Settings::Convergence::RMS))
        throw InputError(std::string(where) + ": invalid settings (unknown convergence test "
                         + std::to_string(cv) + "; tests: Max, RMS)");
    if (S.convergence == System::Settings::Convergence::RMS
        && (!(S.rmsTolerance > 0) || !std::isfinite(S.rmsTolerance)))
        throw InputError(std::string(where) + ": invalid settings (need rmsTolerance > 0 and finite, got "
                         + std::to_string(S.rmsTolerance) + ")");
    if (S.convergence == System::Settings::Convergence::RMS
        && (S.method == System::Settings::Method::APGD || S.method == System::Settings::Method::NNCG
            || S.method == System::Settings::Method::Newton))
        throw InputError(std::string(where)
                         + ": invalid settings (the RMS convergence test is that of the "
                           "Gauss-Seidel methods NLGS and OverRelaxedNLGS; APGD and NNCG use Max, Newton "
                           "its own (newtonTolerance))");
    if (!(S.heatTolerance > 0) || S.heatMaxIterations < 1)
        throw InputError(std::string(where)
                         + ": invalid settings (need heatTolerance > 0, heatMaxIterations >= 1)");
    if (S.reorderInterval < 0)
        throw InputError(std::string(where) + ": invalid settings (need reorderInterval >= 0, got "
                         + std::to_string(S.reorderInterval) + "; 0 switches the reordering off)");
    if (S.cohesionMinAge < 0)
        throw InputError(std::string(where) + ": invalid settings (need cohesionMinAge >= 0, got "
                         + std::to_string(S.cohesionMinAge) + ")");
}

void System::Impl::checkComplianceMethod(const char* where) const
{
    if (settings.method == System::Settings::Method::APGD && anyCompliance())
        throw InputError(std::string(where)
                         + ": a material has a contact compliance (compliance or "
                           "relativeCompliance > 0), which the APGD method does not solve; use NLGS, "
                           "OverRelaxedNLGS or NNCG, or set both to 0");
    if (settings.method != System::Settings::Method::Newton) return;
    // Newton solves the regularised (compliant) problem only: every
    // contact needs a compliance, i.e. every grain's material
    const int N = int(x.size());
    for (int i = 0; i < N; ++i)
    {
        const Material& m = materials[mat[i]];
        if (!(m.compliance > 0 || m.relativeCompliance > 0))
            throw InputError(
                std::string(where)
                + ": the Newton contact solver needs a contact compliance on "
                  "every contact, but grain "
                + std::to_string(i) + " has material " + std::to_string(mat[i])
                + " with compliance = relativeCompliance = 0 (the hard "
                  "law); give that material a compliance or relativeCompliance > 0, or use NLGS");
    }
    if (!droplets.empty())
        throw InputError(std::string(where)
                         + ": the Newton contact solver does not solve droplet contacts "
                           "(hard, capped by the capillary entry force); remove the droplets or use NLGS");
}

StepReport System::step(double dt)
{
    if (!(dt > 0) || !std::isfinite(dt))
        throw InputError("nscd::System::step: dt must be > 0, got " + std::to_string(dt));
    Impl& I = *impl_;
    Impl::checkSettings(I.settings, "nscd::System::step");
    I.checkComplianceMethod("nscd::System::step");
    for (const Droplet& d : I.droplets) checkDroplet(d, "nscd::System::step");
    for (Droplet& d : I.droplets)
        if (d.grainImpulse.size() != I.x.size()) d.grainImpulse.assign(I.x.size(), 0.0);
    const bool heat = I.heatCheck(); // throws before anything is changed
    StepReport rep;
    Impl::StepHooks undecomposed(I);
    I.runStages(dt, I.rMin(), heat, rep, undecomposed); // one scan of the radii for the step
    return rep;
}

void System::Impl::runStages(double dt, double rMinStep, bool heat, StepReport& rep, StepHooks& H)
{
    rep.substeps = 1;
    const StepRMin stepRMin(*this, rMinStep);
    syncKeptContacts(); // after grains were added
    maybeReorder();     // internal slot order along the Morton curve (Reorder.cpp)
    freeVelocities(dt);
    // detect, prepareContacts (+ warm start), buildAdjacency, solveContacts;
    // again with larger reaches if a grain leaves its reach
    const int NC0 = detectAndSolve(dt, rep, H);
    relaxPushOut(dt, rep, H); // overlap correction without velocity
    H.limitEnergy(dt, rep);   // a capped solve may not raise the kinetic energy
    H.integrate(dt, NC0);
    H.storeImpulses(dt, NC0, rep);
    if (H.any(heat))
    {
        using clock = std::chrono::steady_clock;
        const auto t2 = clock::now();
        H.heat(dt, rep);
        rep.heatSeconds = std::chrono::duration<double>(clock::now() - t2).count();
    }
}

int System::Impl::detectAndSolve(double dt, StepReport& rep, StepHooks& H)
{
    using clock = std::chrono::steady_clock;
    const int N = int(x.size());
    reachFloor.clear();
    const long builds = verlet.builds;
    int sweeps = 0;
    long solves = 0;
    for (int redo = 0;; ++redo)
    {
        const auto t0 = clock::now();
        detect(dt);
        const int NCd = int(newContacts.size()); // grain-grain and grain-wall contacts
        detectDroplets(dt);                      // then grain-droplet ones
        const int NC0 = H.ownContacts(NCd);
        const auto t1 = clock::now();
        rep.detectSeconds += std::chrono::duration<double>(t1 - t0).count();
        rep.verletBuilds = int(verlet.builds - builds);

        H.shareMasses();
        prepareContacts(dt, NC0); // warm start and adjacency counts included
        buildAdjacency();
        H.warmStartInterface();
        if (redo > 0) rep.residualHistory.clear();
        H.solve(dt, rep, nullptr);
        rep.solveSeconds += std::chrono::duration<double>(clock::now() - t1).count();
        sweeps += rep.sweeps;
        solves += rep.localSolves;
        if (redo == maxRedetections || !H.any(raiseReaches(dt)))
        {
            rep.sweeps = sweeps;
            rep.localSolves = solves;
            return NC0;
        }
        ++rep.redetections;
        // the bodies as before the solve, with the raised reaches (none
        // here when another system raised them)
        freeVelocities(dt);
        if (!reachFloor.empty())
            for (int i = 0; i < N; ++i) speed[i] = std::max(speed[i], reachFloor[i]);
    }
}

// ---- free velocity (eq. 2.11, with the implicit drag of setFluidDrag) ----
// (bodies, speeds and detection records in slot order, slot s = slotOf[i]
// of grain i. The loop runs over the grains: the per-grain arrays are read
// in their order and only the three slot arrays are written out of order.)
void System::Impl::freeVelocities(double dt)
{
    const int N = int(x.size());
    const int NW = int(walls.size());
    const int ND = int(droplets.size());
    const bool twoD = dim == 2;
    body.resize(N + NW + ND);
    speed.resize(N);
    packed.resize(N);
    for (int i = 0; i < N; ++i)
    {
        const int s = slotOf[i];
        Body& B = body[s];
        GrainSlot& P = packed[s];
        P.x = x[i];
        P.r = rad[i];
        P.mu = materials[mat[i]].friction;
        P.fix = fix[i];
        if (fix[i])
        {
            B.im = B.im0 = 0;
            B.ii = 0;
        }
        else
        {
            B.im = 1.0 / effectiveMass(i, dt);
            B.im0 = 1.0 / mass[i];
            B.ii = rotLock[i] ? 0.0 : 1.0 / inertia[i];
        }
        Vec3 vi, wi;
        freeBodyVelocity(i, dt, B.ii, vi, wi);
        B.v = vi;
        B.w = wi;
        B.r = rad[i];
        speed[s] = vi.norm() + B.r * wi.norm();
    }
    for (int k = 0; k < NW; ++k)
    {
        Body& B = body[N + k];
        B.v = walls[k].velocity;
        B.w.setZero();
        B.im = B.ii = B.r = B.im0 = 0;
    }
    for (int k = 0; k < ND; ++k)
    {
        // droplet: translation only, its own forces (no System gravity)
        const Droplet& D = droplets[k];
        Body& B = body[N + NW + k];
        B.im = B.im0 = D.mass > 0 ? 1.0 / D.mass : 0.0;
        B.v = D.velocity + dt * B.im * D.force;
        if (twoD) B.v.z() = 0;
        B.w.setZero();
        B.ii = B.r = 0;
    }
}

void System::Impl::freeBodyVelocity(int i, double dt, double ii, Vec3& vf, Vec3& wf) const
{
    vf = fix[i] ? v[i] : freeVelocity(i, dt);
    wf = fix[i] ? w[i] : Vec3(w[i] + dt * ii * torque[i]);
    if (dim == 2)
    {
        vf.z() = 0;
        wf.x() = 0;
        wf.y() = 0;
    }
}

Vec3 System::Impl::freeVelocity(int i, double dt) const
{
    const Vec3 vf = v[i] + dt * (g + force[i] / mass[i]);
    const double c = dragCoefficient[i];
    if (c == 0) return vf;
    return (mass[i] * vf + dt * c * dragVelocity[i]) / effectiveMass(i, dt);
}

// ---- contact constants, age, cohesion, warm-start impulses ----
bool System::Impl::prepareContacts(double dt, int NC0)
{
    const int N = int(x.size());
    std::vector<Contact>& C = newContacts;
    const int NC = int(C.size());
    rows.resize(NC);
    const double rmin = rMin();
    const double cohDist = settings.cohesionDistance * rmin;
    const double slop = settings.overlapSlop * rmin;
    const bool cohesion = cohesionForce > 0 && bool(cohesionPredicate);
    const int minAge = settings.cohesionMinAge;
    // previous contacts indexed by i: matched for the warm start and the
    // contact age (the age is tracked also without warm start)
    const std::vector<Contact>& P = contacts;
    const bool match = !P.empty();
    const bool warm = settings.warmStart && match && lastDt > 0;
    // the previous contacts of grain c.i: P is sorted by i, and so are the
    // rows (detect) up to the droplet rows; a cursor walks P along with the
    // rows (no separate pass over P to index it), restarted by a binary
    // search when i decreases
    const int NP = int(P.size());
    int pLo = 0, lastI = -1;
    const double scale = warm ? dt / lastDt : 0.0;
    const bool twoD = dim == 2;
    const int NB = int(body.size());
    adjStart.assign(NB + 1, 0);
    pairs.resize(NC);
    relaxSeed.clear();
    // contact compliance (Material::compliance, relativeCompliance) of each
    // slot's material, only when some material has one
    const bool compliant = anyCompliance();
    if (compliant)
    {
        slotCompliance.resize(N);
        for (int sl = 0; sl < N; ++sl)
        {
            const Material& m = materials[mat[order[sl]]];
            slotCompliance[sl] = {m.compliance, m.relativeCompliance};
        }
    }
    const double idt2 = 1.0 / (dt * dt);
    for (int k = 0; k < NC; ++k)
    {
        if (k + bodiesAhead < NC) // the bodies of a later row (random access: a hint)
        {
            prefetch(&body[C[k + bodiesAhead].i], sizeof(Body));
            prefetch(&body[C[k + bodiesAhead].j], sizeof(Body));
        }
        Contact& c = C[k];
        SolverContact& s = rows[k];
        const Body& A = body[c.i];
        const Body& B = body[c.j];
        s.i = c.i;
        s.j = c.j;
        s.n = c.n;
        s.mu = c.mu;
        s.cap = c.cap;
        s.wnn = A.im + B.im;
        s.wtt = A.im + B.im + A.r * A.r * A.ii + B.r * B.r * B.ii;
        s.iwnn = s.wnn > 0 ? 1.0 / s.wnn : 0.0;
        s.iwtt = s.wtt > 0 ? 1.0 / s.wtt : 0.0;
        {
            // capped: a grain with c dt/m beyond the cap is locked to its
            // fluid velocity (e.g. eps clipped at epsMin), its velocity, not
            // its drag, is what matters, and round-off would stall the test
            const double k = s.wnn > 0 ? std::min((A.im0 + B.im0) / s.wnn, maxResidualWeight) : 1.0;
            s.residualWeight2 = k * k;
        }
        // the contact's law (ContactLaws.H): compliant if its materials
        // have a compliance (the normal diagonal W_nn + eps; its gap term
        // after the warm start, below), else the hard law with the slop band
        // and push-out (droplet rows k >= NC0: the hard law exactly)
        double eps = 0;
        if (compliant && k < NC0)
        {
            const std::array<double, 2>& a = slotCompliance[c.i];
            double cc = a[0], beta = a[1];
            if (c.j < N)
            {
                cc = law::CompliantSignorini::pair(cc, slotCompliance[c.j][0]);
                beta = law::CompliantSignorini::pair(beta, slotCompliance[c.j][1]);
            }
            eps = law::CompliantSignorini::regularisation(cc, beta, s.wnn, idt2);
        }
        if (eps > 0)
            s.iwnn = 1.0 / (s.wnn + eps);
        else
        {
            s.bias = law::HardSignorini::bias(c.gap, dt, slop, k < NC0);
            if (k < NC0 && law::HardSignorini::pushesOut(s.bias)) relaxSeed.push_back(k); // relaxPushOut
        }
        s.rn = 0;
        s.rt.setZero();
        s.change = 0;
        s.coh = 0;
        c.age = 0;
        // the same contact in the previous step: same bodies, normal within 60 degrees
        int best = -1;
        if (match)
        {
            if (c.i < lastI)
                pLo = int(
                    std::lower_bound(P.begin(), P.end(), c.i, [](const Contact& a, int i) { return a.i < i; })
                    - P.begin());
            else
                while (pLo < NP && P[pLo].i < c.i) ++pLo;
            lastI = c.i;
            double bestDot = 0.5;
            for (int p = pLo; p < NP && P[p].i == c.i; ++p)
            {
                if (P[p].j != c.j) continue;
                const double dd = P[p].n.dot(c.n);
                if (dd > bestDot)
                {
                    bestDot = dd;
                    best = p;
                }
            }
            if (best >= 0) c.age = P[best].age;
        }
        // cohesion (eq. 4.18): close, persistent, and the user's condition
        if (cohesion && k < NC0 && law::Cohesion::eligible(c.gap, cohDist, c.age, minAge))
        {
            // grains, a grain pair with i < j (as contacts())
            const int gi = order[c.i], gj = c.j < N ? order[c.j] : -(c.j - N + 1);
            const bool pair = gj >= 0;
            if (cohesionPredicate(pair ? std::min(gi, gj) : gi, pair ? std::max(gi, gj) : gj))
                s.coh = law::Cohesion::impulse(cohesionForce, dt);
        }
        if (warm && best >= 0)
        {
            const Vec3 imp = scale * (P[best].rn * P[best].n + P[best].rt);
            s.rn = std::max(-s.coh, imp.dot(c.n));
            s.rt = imp - imp.dot(c.n) * c.n;
            const double lim = s.mu * (s.rn + s.coh);
            const double tn = s.rt.norm();
            if (tn > lim) s.rt *= (tn > 0 ? lim / tn : 0.0);
            warmStart(s);
        }
        // compliant contact: its gap term with the slop band around the
        // equilibrium gap of the warm-start force (ContactLaws.H)
        if (eps > 0) s.bias = law::CompliantSignorini::bias(c.gap, eps, s.rn, dt, slop);
        // 2D: the scalar tangential impulse of the NLGS solve (its start() step)
        if (twoD) s.rts = s.rt.dot(Vec3(-s.n.y(), s.n.x(), 0.0));
        // adjacency counts (buildAdjacency): rows of each movable body
        const bool mi = !packed[c.i].fix, mj = c.j < N ? !packed[c.j].fix : body[c.j].im > 0;
        if (mi) ++adjStart[c.i + 1];
        if (mj) ++adjStart[c.j + 1];
        pairs[k] = {mi ? c.i : -1, mj ? c.j : -1};
    }
    rowsHaveRts = twoD;
    return warm;
}

void System::Impl::warmStart(const SolverContact& c)
{
    if (c.rn == 0 && c.rt.isZero()) return;
    Body& A = body[c.i];
    Body& B = body[c.j];
    const Vec3 Pm = c.rn * c.n + c.rt;
    const Vec3 nxt = c.n.cross(c.rt);
    A.v += A.im * Pm;
    A.w -= A.ii * A.r * nxt;
    B.v -= B.im * Pm;
    B.w -= B.ii * B.r * nxt;
}

// ---- adjacency (contacts of each movable body), from the counts of prepareContacts ----
// (bodies of all kinds; walls and fixed grains have none, a movable
// droplet lists its contacts: a change of its velocity re-flags them)
void System::Impl::buildAdjacency()
{
    const int NB = int(body.size());
    const int NC = int(rows.size());
    for (int i = 0; i < NB; ++i) adjStart[i + 1] += adjStart[i];
    adjItems.resize(adjStart[NB]);
    cellOf.assign(adjStart.begin(), adjStart.end() - 1); // cursor
    for (int k = 0; k < NC; ++k)
    {
        const std::array<int, 2>& p = pairs[k];
        if (p[0] >= 0) adjItems[cellOf[p[0]]++] = k;
        if (p[1] >= 0) adjItems[cellOf[p[1]]++] = k;
    }
}

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

// ---- relax stage: the overlap correction moves grains, gives no velocity ----
void System::Impl::relaxPushOut(double dt, StepReport& rep, StepHooks& H)
{
    relaxPositionVelocity.clear();
    if (!H.any(!relaxSeed.empty())) return; // (filled by prepareContacts)
    holdPositionVelocities();
    for (int k : relaxSeed) rows[k].bias = 0.0;
    // the solve continues from the rows' impulses and the bodies' velocities;
    // after a converged solve only the push-out rows have a new law (the
    // others are converged at these velocities): they alone are queued
    StepReport relax;
    H.solve(dt, relax, rep.converged ? &relaxSeed : nullptr);
    mergeRelaxReport(rep, relax);
}

void System::Impl::holdPositionVelocities()
{
    const int N = int(x.size());
    relaxPositionVelocity.resize(N);
    for (int s = 0; s < N; ++s) relaxPositionVelocity[s] = body[s].v;
}

// ---- a capped (unconverged) solve may not raise the kinetic energy ----
// For the dissipative law (inelastic Signorini with bias >= 0, Coulomb
// friction, static walls, no cohesion or droplet) the exact solution only
// removes energy from the free velocities, but a warm-started Gauss-Seidel
// stopped at maxIterations can leave impulses that add energy (a deep
// frictionless column: 40-fold in one step, docs/validation/dropletDigging.md,
// "Eighteenth session"). Then the contact impulses r are scaled to alpha r,
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

// ---- impulses into the persistent records, age (closed: loaded or touching) ----
void System::Impl::storeImpulses(double dt, int NC0, StepReport& rep)
{
    const double xi = settings.tolerance * (2 * rMin()); // as the solver's xi
    std::vector<Contact>& C = newContacts;
    lastDt = dt;
    double ov = 0;
    int nCoh = 0;
    for (int k = 0; k < NC0; ++k)
    {
        Contact& c = C[k];
        const SolverContact& s = rows[k];
        c.rn = s.rn;
        c.rt = s.rt;
        c.wnn = s.wnn;
        c.wtt = s.wtt;
        c.bias = s.bias;
        c.coh = s.coh;
        c.change = s.change;
        const double gapNow = contactGapNow(c);
        ov = std::max(ov, -gapNow);
        const bool closed = c.rn + c.coh > 0 || gapNow <= xi;
        c.age = closed ? c.age + 1 : 0;
        if (c.coh > 0) ++nCoh;
    }
    rep.maxOverlap = ov;
    rep.cohesiveContacts = nCoh;
    // droplet contacts are not kept (no warm start, views, heat or I/O)
    C.resize(NC0);
    std::swap(contacts, newContacts);
}

} // namespace nscd
