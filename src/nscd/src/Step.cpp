// SPDX-License-Identifier: GPL-3.0-or-later
// System::step in named stages, shared with the decomposed step
// (Subdomain.cpp) through System::Impl::StepHooks; the stages' work is in
// ContactRows.cpp (the solver rows from the contact records and back),
// ContactSolver*.cpp (the solve) and Integrate.cpp (the end of the step).
//
// Layout, in the manner of Box2D v3 (E. Catto, solver.c / contact_solver.c):
// the persistent contact records (Impl::contacts, struct Contact: bodies,
// normal, impulses, age) outlive the step; the solver works on scratch rows
// (Impl::rows, struct SolverContact) built from the detected contacts by
// prepareContacts and written back by storeImpulses.
//
//   validate -> freeVelocities -> [detect -> prepareContacts (+ warmStart of
//   each row) -> buildAdjacency -> solveContacts] (detectAndSolve: repeated
//   with larger reaches if a grain leaves its reach) -> relaxPushOut ->
//   limitCappedEnergy -> integrate -> storeImpulses -> heat
#include "StepHooks.H"
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
    const int fl = int(S.frictionLaw);
    if (fl < 0 || fl > int(System::Settings::FrictionLaw::Anitescu))
        throw InputError(std::string(where) + ": invalid settings (unknown friction law " + std::to_string(fl)
                         + "; laws: Coulomb, Anitescu)");
    if (S.frictionLaw == System::Settings::FrictionLaw::Anitescu
        && S.method == System::Settings::Method::APGD)
        throw InputError(std::string(where)
                         + ": invalid settings (FrictionLaw::Anitescu is solved by the Gauss-Seidel methods "
                           "NLGS, OverRelaxedNLGS and NNCG, and by Newton; APGD solves the Coulomb law)");
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
        if (!m.compliant())
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

// The implicit drag c (u - v^+) of setFluidDrag enters the contact problem
// itself: the free velocity becomes
//   v_free = (m (v + dt g) + dt F + dt c u)/(m + dt c)
// (F the external force, without the drag) and the grain's translational
// mass in the Delassus operator is m + dt c, so v^+ = v_free + (contact
// impulses)/(m + dt c). A grain held by its contacts therefore feels this
// step's drag and its contact impulses together, stable for any c dt/m
// (fine grains in a liquid reach c dt/m ~ 1e4).
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

} // namespace nscd
