// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::Subdomain: the step of one subdomain of a decomposed grain system
// (Subdomain.H): the stages of System::step (Step.cpp) with the contacts
// this subdomain owns, copy masses for the interface grains and an NLGS
// whose sweeps alternate with the averaging of the copies' velocities.
#include "nscd/Subdomain.H"

#include "LocalSolve.H"
#include "SubdomainHeat.H"
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>
#include <string>

namespace nscd
{

/// Scratch of the decomposed step, kept between steps (no allocation in steady state).
struct Subdomain::Scratch
{
    std::vector<int> iface;       ///< interface grains (copies > 1, movable)
    std::vector<Vec3> vAvg, wAvg; ///< per grain: velocities for averageCopies
    std::vector<char> inContact;  ///< per grain: body of a contact here
    std::vector<int> copies;      ///< per grain: copies in this step's solve
    std::vector<Vec3> lambda;     ///< per interface grain (aligned with iface), 2 each: its copy's
                                  ///< interface impulses in this step (linear, angular)
    std::vector<char> ifaceRow;   ///< per row: a body is an interface grain
    std::vector<int> ifaceRows;   ///< the rows flagged in ifaceRow
    std::vector<System::Impl::DragInterfaceTerm> dragTerms; ///< per interface grain: its drag impulse's terms
    std::vector<int> dropletBodies;  ///< bodies of the droplets with mass (averaged over the subdomains)
    std::vector<char> dropletShared; ///< per droplet: a contact of it is solved here
    std::vector<double> dropletV, dropletW; ///< per droplet, 3 each: weightedMeanOverSubdomains buffers
};

/// Kept from step to step (apart from the scratch): the interface impulses
/// of the last step, by global id (local indices change at every exchange).
/// Only the grains that had copies in the last step's solve have one, so the
/// subdomain keeps no per-grain list for them.
struct Subdomain::InterfaceImpulses
{
    std::vector<long> id;      ///< global ids, ascending
    std::vector<Vec3> impulse; ///< 2 per id: linear [N s], angular [N m s] (2D: per unit depth)
};

namespace
{
/// Queue prefetch distances, as the undecomposed NLGS (ContactSolver.cpp).
constexpr int rowsAhead = 16, bodiesAhead = 8;

/// An interface grain whose averaged velocity moves a contact point by more
/// than this fraction of the solver's xi = tolerance d_min in dt queues its
/// contacts again (below it the copies agree to within the tolerance).
constexpr double requeueFraction = 0.5;

/**
 * One averaging of the interface grains' copies (X.iface): their velocities
 * replaced by the average over the copies (averageCopies), the impulse this
 * gives each copy, M (v_avg - v), added to its interface impulse (X.lambda,
 * 2 entries per interface grain, aligned with X.iface);
 * moved(slot, du) is called with each copy's velocity change |dv| + r |dw|.
 */
template <class Moved>
void averageInterface(System::Impl& I, SubdomainCoupling& C, Subdomain::Scratch& X, Moved moved)
{
    std::vector<Vec3>& lambda = X.lambda;
    for (int i : X.iface)
    {
        const Body& B = I.body[I.slotOf[i]];
        X.vAvg[i] = B.v;
        X.wAvg[i] = B.w;
    }
    C.averageCopies(X.vAvg, X.wAvg);
    for (std::size_t k = 0; k < X.iface.size(); ++k)
    {
        const int i = X.iface[k];
        const int s = I.slotOf[i];
        Body& B = I.body[s];
        const double du = (X.vAvg[i] - B.v).norm() + B.r * (X.wAvg[i] - B.w).norm();
        if (B.im > 0) lambda[2 * k] += (X.vAvg[i] - B.v) / B.im;
        if (B.ii > 0) lambda[2 * k + 1] += (X.wAvg[i] - B.w) / B.ii;
        B.v = X.vAvg[i];
        B.w = X.wAvg[i];
        moved(s, du);
    }
    // droplets with mass: the mean of the copies of the subdomains that
    // solve one of its contacts, the same on every subdomain (a subdomain
    // without its contacts takes it too)
    if (X.dropletBodies.empty()) return;
    const int b0 = int(I.x.size() + I.walls.size());
    const int ND = int(I.droplets.size());
    X.dropletV.assign(3 * ND, 0.0);
    X.dropletW.assign(3 * ND, 0.0);
    for (int b : X.dropletBodies)
        for (int c = 0; c < 3; ++c)
        {
            X.dropletV[3 * (b - b0) + c] = I.body[b].v[c];
            X.dropletW[3 * (b - b0) + c] = X.dropletShared[b - b0] ? 1.0 : 0.0;
        }
    C.weightedMeanOverSubdomains(X.dropletV, X.dropletW);
    for (int b : X.dropletBodies)
    {
        const Vec3 v(X.dropletV[3 * (b - b0)], X.dropletV[3 * (b - b0) + 1], X.dropletV[3 * (b - b0) + 2]);
        const double du = (v - I.body[b].v).norm();
        I.body[b].v = v;
        moved(b, du);
    }
}

/**
 * The interface-averaged NLGS on the rows of I (prepared): rounds of one
 * sweep-equivalent of the FIFO contact queue (section 2.3), or until it
 * empties, then averageCopies of the interface grains, so that the
 * interface keeps in step with the subdomains (a subdomain solved to
 * convergence against interface impulses far from theirs can drift far from
 * the solution); the rows of a grain whose velocity the averaging moved by
 * more than requeueFraction xi/dt are queued again. When no
 * subdomain has a queued row, every row's last change is below the
 * tolerance (a row whose change was not is queued again) except possibly
 * the rows of the interface grains, whose velocities the averagings moved
 * by less than the requeue threshold: those are evaluated at the final
 * velocities and queued again if off by more than the tolerance. The pass
 * over every row that finishes them (and gives the residual, eq. in
 * ContactSolver.cpp) is made once, when the solve stops, not at each such
 * re-entry (several a step on a 3D interface), where it would cost two
 * memory-bound passes over the rows. Stops converged
 * (global residual <= tolerance) or capped (Settings::maxIterations
 * averagings or sweep-equivalents of local solves). seed: rows queued at
 * the start (null: all; a seeded solve continues a converged solve of the
 * same rows, as System::Impl::solveNLGS: the rows it does not solve keep
 * their tangential impulse and change, whose residual the solve it continues
 * bounds). The averagings' impulses are added to the interface impulses
 * of the copies (X.lambda, per interface grain of X.iface: linear,
 * angular). Fills rep (sweeps:
 * sweep-equivalents of local solves; global residual).
 */
void solveDecomposed(System::Impl& I, SubdomainCoupling& C, Subdomain::Scratch& X, double dt, double dmin,
                     StepReport& rep, const std::vector<int>* seed)
{
    const int NC = int(I.rows.size());
    const bool twoD = I.dim == 2;
    const double xi = I.settings.tolerance * dmin;
    const double xi2 = xi * xi, dt2 = dt * dt;
    SolverContact* const cs = I.rows.data();
    Body* const bodies = I.body.data();
    const int* const adjS = I.adjStart.data();
    const int* const adjI = I.adjItems.data();
    // 2D scalar tangential impulses (a seeded solve keeps those of the
    // solve it continues)
    if (twoD && !I.rowsHaveRts && !seed)
        for (int k = 0; k < NC; ++k) cs[k].rts = cs[k].rt.dot(Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0));
    I.rowsHaveRts = false;

    const std::vector<int>& iface = X.iface;

    // FIFO queue as a ring of NC entries (each row at most once)
    I.queue.resize(std::max(NC, 1));
    I.inQueue.assign(NC, 0);
    int* const queue = I.queue.data();
    char* const inQ = I.inQueue.data();
    int head = 0, count = 0;
    auto push = [&](int k)
    {
        if (inQ[k]) return;
        inQ[k] = 1;
        int tail = head + count;
        if (tail >= NC) tail -= NC;
        queue[tail] = k;
        ++count;
    };
    auto pushBody = [&](int b)
    {
        for (int p = adjS[b]; p < adjS[b + 1]; ++p) push(adjI[p]);
    };
    if (seed)
        for (int k : *seed) push(k);
    else
        for (int k = 0; k < NC; ++k) push(k);
    // the rows a seeded solve solves (the others keep their change, already
    // a square root, and are not visited again)
    std::vector<int>& solved = I.seedSolved;
    std::vector<char>& solvedFlag = I.seedSolvedFlag;
    solved.clear();
    if (seed) solvedFlag.assign(NC, 0);

    // rows of the interface grains: the averagings move their velocities
    std::vector<char>& ifaceRow = X.ifaceRow;
    std::vector<int>& ifaceRows = X.ifaceRows;
    ifaceRow.assign(NC, 0);
    ifaceRows.clear();
    auto flagRows = [&](int b)
    {
        for (int p = adjS[b]; p < adjS[b + 1]; ++p)
            if (!ifaceRow[adjI[p]])
            {
                ifaceRow[adjI[p]] = 1;
                ifaceRows.push_back(adjI[p]);
            }
    };
    for (int i : iface) flagRows(I.slotOf[i]);
    for (int b : X.dropletBodies) flagRows(b); // (averaged as well)
    // residual (ContactSolver.cpp), squared: the last change of each row
    // solved, evaluated at the current velocities for the rows of interface
    // grains. In the same pass the rows are finished (2D tangential impulse
    // back to a vector, change to its square root: one pass over the rows,
    // which are memory-bound), once, when the solve stops.
    auto rowResidual2 = [&](int k) // at the current velocities
    {
        const SolverContact& c = cs[k];
        const Vec3 rt = twoD ? Vec3(c.rts * Vec3(-c.n.y(), c.n.x(), 0.0)) : c.rt;
        return localResidual2(c, rt, bodies[c.i], bodies[c.j], dt);
    };
    auto finishRow = [&](int k, double& r)
    {
        SolverContact& c = cs[k];
        if (!ifaceRow[k]) r = std::max(r, c.change);
        if (twoD) c.rt = c.rts * Vec3(-c.n.y(), c.n.x(), 0.0);
        c.change = std::sqrt(c.change);
    };
    auto residual2AndFinish = [&]()
    {
        double r = 0;
        if (seed)
            for (int k : solved) finishRow(k, r);
        else
            for (int k = 0; k < NC; ++k) finishRow(k, r);
        for (int k : ifaceRows) r = std::max(r, rowResidual2(k));
        return r;
    };

    const long maxSolves = long(I.settings.maxIterations) * long(std::max(NC, 1));
    long solves = 0;
    int averagings = 0;
    bool busy = true;
    bool capped = false; // some subdomain reached maxSolves (global)
    double res = 0;
    for (;;)
    {
        while (busy && !capped && averagings < I.settings.maxIterations)
        {
            // one sweep-equivalent of local solves (or the queue emptied)
            for (long budget = std::max(NC, 1); count > 0 && solves < maxSolves && budget > 0; --budget)
            {
                const int k = queue[head];
                head = head + 1 == NC ? 0 : head + 1;
                --count;
                // the rows and bodies ahead in the queue (as the undecomposed
                // NLGS, ContactSolver.cpp: a hint, results unchanged)
                if (count > rowsAhead)
                    prefetch(cs + queue[head + rowsAhead >= NC ? head + rowsAhead - NC : head + rowsAhead],
                             sizeof(SolverContact));
                if (count > bodiesAhead)
                {
                    const SolverContact& a =
                        cs[queue[head + bodiesAhead >= NC ? head + bodiesAhead - NC : head + bodiesAhead]];
                    prefetch(bodies + a.i, sizeof(Body));
                    prefetch(bodies + a.j, sizeof(Body));
                }
                inQ[k] = 0;
                ++solves;
                if (seed && !solvedFlag[k])
                {
                    solvedFlag[k] = 1;
                    solved.push_back(k);
                }
                SolverContact& c = cs[k];
                const bool changed = twoD ? local::update2D(c, bodies[c.i], bodies[c.j], dt2, xi2, 1.0)
                                          : local::update3D(c, bodies[c.i], bodies[c.j], dt2, xi2, 1.0);
                if (!changed) continue;
                push(k);
                pushBody(c.i);
                pushBody(c.j);
            }
            averageInterface(I, C, X,
                             [&](int s, double du)
                             {
                                 if (du * dt > requeueFraction * xi) pushBody(s);
                             });
            ++averagings;
            double flags[2] = {count > 0 ? 1.0 : 0.0, solves >= maxSolves ? 1.0 : 0.0};
            C.maxOverSubdomainsEach(flags, 2); // one reduction for both
            busy = flags[0] > 0;
            capped = flags[1] > 0;
        }
        if (busy || capped || averagings >= I.settings.maxIterations) break;
        // no queued row anywhere: the copies agree to the requeue threshold,
        // but a row of an interface grain may be off by more than the
        // tolerance (the other rows are not, see above): those rows again.
        // A row off here makes the residual exceed the tolerance, and none
        // off means it does not: the same decision as the residual's.
        for (int k : ifaceRows)
            if (rowResidual2(k) > xi2) push(k);
        busy = C.maxOverSubdomains(count > 0 ? 1.0 : 0.0) > 0;
        if (!busy) break;
    }
    res = C.maxOverSubdomains(std::sqrt(residual2AndFinish()));
    rep.contacts = std::max(rep.contacts, NC);
    rep.localSolves += solves;
    rep.sweeps += NC > 0 ? int((solves + NC - 1) / NC) : 0;
    rep.residual = std::max(rep.residual, dmin > 0 ? res / dmin : 0.0);
    rep.converged = rep.converged && !busy && !capped && res <= xi;
}
/**
 * The interface impulses of the last step (last, by global id) as the warm
 * start of this one: zero for a grain with one copy (or a ghost in no
 * contact here); the others made to sum to zero over the grain's copies
 * (the set of copies may have changed: their mean is removed, through
 * averageCopies), scaled by dt/lastDt as the contact impulses, and applied
 * to the copy's body; then one averaging of the copies' velocities. Lists
 * the interface grains (X.iface) and sets their impulses (X.lambda). A
 * re-detection calls it again with the same last impulses.
 */
void warmStartInterface(System::Impl& I, SubdomainCoupling& C, Subdomain::Scratch& X,
                        const std::vector<char>& owned, const std::vector<long>& globalId,
                        const Subdomain::InterfaceImpulses& last, double scale)
{
    const int N = int(I.x.size());
    // the interface grains of this step (their copies average in the solve)
    X.iface.clear();
    for (int i = 0; i < N; ++i)
        if ((owned[i] || X.inContact[i]) && X.copies[i] > 1 && !I.fix[i]) X.iface.push_back(i);
    std::vector<Vec3>& lambda = X.lambda;
    lambda.assign(2 * X.iface.size(), Vec3::Zero());
    for (std::size_t k = 0; k < X.iface.size(); ++k)
    {
        const long id = globalId[X.iface[k]];
        const auto it = std::lower_bound(last.id.begin(), last.id.end(), id);
        if (it == last.id.end() || *it != id) continue;
        const std::size_t n = std::size_t(it - last.id.begin());
        lambda[2 * k] = last.impulse[2 * n];
        lambda[2 * k + 1] = last.impulse[2 * n + 1];
    }
    X.vAvg.resize(N);
    X.wAvg.resize(N);
    for (std::size_t k = 0; k < X.iface.size(); ++k)
    {
        X.vAvg[X.iface[k]] = lambda[2 * k];
        X.wAvg[X.iface[k]] = lambda[2 * k + 1];
    }
    C.averageCopies(X.vAvg, X.wAvg);
    for (std::size_t k = 0; k < X.iface.size(); ++k)
    {
        const int i = X.iface[k];
        lambda[2 * k] = scale * (lambda[2 * k] - X.vAvg[i]);
        lambda[2 * k + 1] = scale * (lambda[2 * k + 1] - X.wAvg[i]);
        Body& B = I.body[I.slotOf[i]];
        B.v += B.im * lambda[2 * k];
        B.w += B.ii * lambda[2 * k + 1];
    }
    // the copies made to agree before the first sweep: with warm-started
    // contacts their average is the undecomposed warm-started velocity, and
    // the local sweeps start from it rather than from each copy's share
    averageInterface(I, C, X, [](int, double) {});
}

/// The interface impulses of this step (X.iface, X.lambda), non-zero ones,
/// kept by global id for the next step's warm start.
void keepInterface(const Subdomain::Scratch& X, const std::vector<long>& globalId,
                   Subdomain::InterfaceImpulses& last)
{
    std::vector<std::pair<long, std::size_t>> byId;
    for (std::size_t k = 0; k < X.iface.size(); ++k)
        if (X.lambda[2 * k] != Vec3::Zero()
            || X.lambda[2 * k + 1] != Vec3::Zero()) // (exact; isZero has a tolerance)
            byId.emplace_back(globalId[X.iface[k]], k);
    std::sort(byId.begin(), byId.end());
    last.id.resize(byId.size());
    last.impulse.resize(2 * byId.size());
    for (std::size_t n = 0; n < byId.size(); ++n)
    {
        last.id[n] = byId[n].first;
        last.impulse[2 * n] = X.lambda[2 * byId[n].second];
        last.impulse[2 * n + 1] = X.lambda[2 * byId[n].second + 1];
    }
}
} // namespace

Subdomain::Subdomain(System& system, SubdomainCoupling& coupling)
    : sys_(system), coupling_(coupling), scratch_(std::make_unique<Scratch>()),
      interface_(std::make_unique<InterfaceImpulses>())
{
}

Subdomain::~Subdomain() = default;

std::size_t Subdomain::rowBytes(unsigned flags) const { return sys_.impl_->columns.rowBytes(flags); }

void Subdomain::packGrain(std::size_t i, unsigned flags, char* out) const
{
    sys_.impl_->columns.packRow(i, flags, out);
}

void Subdomain::unpackGrain(std::size_t i, unsigned flags, const char* in)
{
    System::Impl& I = *sys_.impl_;
    I.columns.unpackRow(i, flags, in);
    if (!std::isfinite(I.rad[i]) || !(I.rad[i] > 0) || I.mat[i] < 0 || I.mat[i] >= int(I.materials.size()))
        throw InputError("nscd::Subdomain::unpackGrain: grain " + std::to_string(i) + ": radius "
                         + std::to_string(I.rad[i]) + ", material " + std::to_string(I.mat[i]) + " of "
                         + std::to_string(I.materials.size()) + " (a row packed with other columns?)");
    I.setMassInertia(i);
}

std::size_t Subdomain::addGrain(unsigned flags, const char* in)
{
    const std::size_t i = sys_.impl_->appendRow();
    try
    {
        unpackGrain(i, flags, in);
    }
    catch (const InputError&)
    {
        sys_.removeGrains({i});
        throw;
    }
    return i;
}

System Subdomain::withoutGrains(const System& s)
{
    System out(s.dimension());
    *out.impl_ = *s.impl_;
    std::vector<std::size_t> all(out.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    out.removeGrains(all);
    return out;
}

void Subdomain::setGrainId(std::size_t i, long id)
{
    if (id < 0) throw InputError("nscd::Subdomain::setGrainId: negative grain id " + std::to_string(id));
    System::Impl& I = *sys_.impl_;
    I.ids.at(i) = id;
    I.nextId = std::max(I.nextId, id + 1);
}

namespace
{
/**
 * The input checks of Subdomain::step, collective: if one subdomain refuses
 * the step, all do (none is left waiting in a collective of the step).
 * @return true if some temperature is integrated here (heatCheck).
 */
bool checkStep(System::Impl& I, SubdomainCoupling& coupling, double dt, const std::vector<char>& owned,
               const std::vector<long>& globalId)
{
    const int N = int(I.x.size());
    std::string refused;
    bool heat = false;
    try
    {
        if (owned.size() != std::size_t(N) || globalId.size() != std::size_t(N))
            throw InputError("nscd::Subdomain::step: owned and globalId need one entry per grain ("
                             + std::to_string(N) + "), got " + std::to_string(owned.size()) + " and "
                             + std::to_string(globalId.size()));
        if (!(dt > 0) || !std::isfinite(dt))
            throw InputError("nscd::Subdomain::step: dt must be > 0, got " + std::to_string(dt));
        for (const System::Droplet& d : I.droplets) checkDroplet(d, "nscd::Subdomain::step");
        System::Impl::checkSettings(I.settings, "nscd::Subdomain::step");
        I.checkComplianceMethod("nscd::Subdomain::step");
        if (I.settings.method == System::Settings::Method::Newton)
            throw InputError("nscd::Subdomain::step: the Newton contact solver is not available with "
                             "decomposed grains (the interface averaging is a Gauss-Seidel's); use NLGS");
        if (I.settings.convergence != System::Settings::Convergence::Max)
            throw InputError("nscd::Subdomain::step: the RMS convergence test is not available with "
                             "decomposed grains (its interface averaging stops on the Max test); use Max");
        heat = I.heatCheck();
    }
    catch (const InputError& e)
    {
        refused = e.what();
    }
    if (coupling.maxOverSubdomains(refused.empty() ? 0.0 : 1.0) > 0)
        throw InputError(refused.empty() ? "nscd::Subdomain::step: another subdomain refused the step"
                                           " (its error names the input)"
                                         : refused);
    return heat;
}

/**
 * The decomposed step's work at the stages of System::Impl::runStages: the
 * contacts this subdomain owns, the copy masses of the interface bodies,
 * the interface warm start, the interface-averaged solve, the decisions
 * taken together, the interface grains' drag and the droplets' impulses
 * summed over the subdomains, the interface impulses kept for the next
 * step, and the heat step of the owned grains. No energy limit of a
 * capped solve (Subdomain.H).
 */
class DecomposedStages : public System::Impl::StepHooks
{
public:
    DecomposedStages(System::Impl& I, SubdomainCoupling& coupling, Subdomain::Scratch& scratch,
                     Subdomain::InterfaceImpulses& last, const std::vector<char>& owned,
                     const std::vector<long>& globalId, double dt)
        : StepHooks(I), C(coupling), X(scratch), last(last), owned(owned), globalId(globalId),
          N(int(I.x.size())), NW(int(I.walls.size())), ND(int(I.droplets.size())),
          warmScale(I.settings.warmStart && I.lastDt > 0 ? dt / I.lastDt : 0.0)
    {
        X.dropletBodies.clear();
        for (int k = 0; k < ND; ++k)
            if (I.droplets[k].mass > 0) X.dropletBodies.push_back(N + NW + k);
        // the tolerance scale d_min of the undecomposed system (collective)
        dmin = -2 * C.maxOverSubdomains(N > 0 ? -I.rMin() : -1e300);
        X.inContact.resize(N);
    }

    /// The undecomposed system's tolerance scale d_min (twice its r_min).
    double dmin = 0;

    /// The contacts this subdomain owns: the owner of the grain with the
    /// smaller global id solves a grain pair, the grain's owner a wall or
    /// droplet contact; their grains flagged in inContact (one pass over the
    /// contacts, which are memory-bound), the droplets in dropletShared.
    int ownContacts(int NC0) override
    {
        std::vector<Contact>& Cs = I.newContacts;
        std::fill(X.inContact.begin(), X.inContact.end(), 0);
        X.dropletShared.assign(ND, 0);
        std::size_t m = 0;
        auto keep = [&](std::size_t from, std::size_t to, bool droplets)
        {
            for (std::size_t k = from; k < to; ++k)
            {
                const Contact& c = Cs[k];
                const int gi = I.order[c.i];
                const int gj = !droplets && c.j < N ? I.order[c.j] : -1;
                if (!owned[gj < 0 || globalId[gi] < globalId[gj] ? gi : gj]) continue;
                X.inContact[gi] = 1;
                if (gj >= 0) X.inContact[gj] = 1;
                if (droplets) X.dropletShared[c.j - N - NW] = 1;
                if (m != k) Cs[m] = c;
                ++m;
            }
        };
        keep(0, std::size_t(NC0), false);
        const int kept = int(m);
        keep(std::size_t(NC0), Cs.size(), true);
        Cs.resize(m);
        return kept;
    }

    /// The interface grains' masses shared among their copies (m/n, J/n for
    /// n copies); a droplet with mass: a copy of mass m/n on each of the n
    /// subdomains that solve one of its contacts.
    void shareMasses() override
    {
        std::vector<int>& copies = X.copies;
        C.countCopies(X.inContact, copies);
        for (int i = 0; i < N; ++i)
        {
            if (!(owned[i] || X.inContact[i]) || copies[i] <= 1) continue;
            Body& B = I.body[I.slotOf[i]];
            B.im *= copies[i];
            B.im0 *= copies[i];
            B.ii *= copies[i];
        }
        for (int b : X.dropletBodies)
        {
            const double n = C.sumOverSubdomains(X.dropletShared[b - N - NW] ? 1.0 : 0.0);
            if (!X.dropletShared[b - N - NW] || !(n > 1)) continue;
            I.body[b].im *= n;
            I.body[b].im0 *= n;
        }
    }

    void warmStartInterface() override
    {
        nscd::warmStartInterface(I, C, X, owned, globalId, last, warmScale);
    }

    /// The interface-averaged solve; rep's solver fields as solveContacts
    /// sets them (the contacts: the most of the step's solves).
    void solve(double dt, StepReport& rep, const std::vector<int>* seed) override
    {
        StepReport r;
        solveDecomposed(I, C, X, dt, dmin, r, seed);
        rep.contacts = std::max(rep.contacts, r.contacts);
        rep.localSolves = r.localSolves;
        rep.sweeps = r.sweeps;
        rep.residual = r.residual;
        rep.converged = r.converged;
    }

    bool any(bool flag) override { return C.maxOverSubdomains(flag ? 1.0 : 0.0) > 0; }

    void limitEnergy(double, StepReport&) override {}

    /// integrate, with the drag impulse of an interface grain from its whole
    /// contact impulse (its copies' contacts here and elsewhere: n (local +
    /// interface)) and a droplet's impulse from the contacts of every
    /// subdomain.
    void integrate(double dt, int NC0) override
    {
        X.dragTerms.resize(X.iface.size());
        for (std::size_t k = 0; k < X.iface.size(); ++k)
            X.dragTerms[k] = {X.iface[k], X.copies[X.iface[k]], X.lambda[2 * k]};
        I.dragInterface = &X.dragTerms;
        std::vector<Vec3> dropletImpulse0(ND);
        for (int k = 0; k < ND; ++k) dropletImpulse0[k] = I.droplets[k].impulse;
        I.integrate(dt, NC0);
        for (int k = 0; k < ND; ++k)
        {
            Vec3& J = I.droplets[k].impulse;
            const Vec3 dJ = J - dropletImpulse0[k];
            for (int c = 0; c < 3; ++c) J[c] = dropletImpulse0[k][c] + C.sumOverSubdomains(dJ[c]);
        }
        I.dragInterface = nullptr;
    }

    /// storeImpulses, and the interface impulses kept for the next step.
    void storeImpulses(double dt, int NC0, StepReport& rep) override
    {
        I.storeImpulses(dt, NC0, rep);
        keepInterface(X, globalId, last);
    }

    void heat(double dt, StepReport& rep) override { decomposedHeatStep(I, C, owned, dt, rep); }

private:
    SubdomainCoupling& C;
    Subdomain::Scratch& X;
    Subdomain::InterfaceImpulses& last;
    const std::vector<char>& owned;
    const std::vector<long>& globalId;
    const int N, NW, ND;
    const double warmScale; ///< dt/lastDt of the warm start (0: none)
};
} // namespace

StepReport Subdomain::step(double dt, const std::vector<char>& owned, const std::vector<long>& globalId)
{
    System::Impl& I = *sys_.impl_;
    const bool heat = checkStep(I, coupling_, dt, owned, globalId);
    for (System::Droplet& d : I.droplets)
        if (d.grainImpulse.size() != I.x.size()) d.grainImpulse.assign(I.x.size(), 0.0);
    DecomposedStages stages(I, coupling_, *scratch_, *interface_, owned, globalId, dt);
    StepReport rep;
    rep.method = int(System::Settings::Method::NLGS);
    // the lengths scaled by r_min are the undecomposed system's for the
    // step (System::Impl::rMinOfStep), restored however the step ends
    I.runStages(dt, 0.5 * stages.dmin, heat, rep, stages);
    return rep;
}

} // namespace nscd
