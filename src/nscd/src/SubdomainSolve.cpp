// SPDX-License-Identifier: GPL-3.0-or-later
// The interface-averaged contact solve of a decomposed step
// (SubdomainSolve.H): the averaging of the interface copies, the NLGS whose
// sweeps alternate with it, the warm start of the interface impulses and
// their keeping for the next step.
#include "SubdomainSolve.H"

#include "LocalSolve.H"

#include <algorithm>
#include <cmath>
#include <utility>

namespace nscd
{

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

/// FIFO queue of rows as a ring of NC entries (each row at most once).
struct RowQueue
{
    int* queue;
    char* inQ;
    int NC;
    int head = 0, count = 0;

    void push(int k)
    {
        if (inQ[k]) return;
        inQ[k] = 1;
        int tail = head + count;
        if (tail >= NC) tail -= NC;
        queue[tail] = k;
        ++count;
    }
    /// The entry `ahead` places after the head (ahead < count).
    int at(int ahead) const { return queue[head + ahead >= NC ? head + ahead - NC : head + ahead]; }
};

/// The stages of solveDecomposed (see SubdomainSolve.H).
class InterfaceSolve
{
public:
    InterfaceSolve(System::Impl& I, SubdomainCoupling& C, Subdomain::Scratch& X, double dt, double dmin,
                   const std::vector<int>* seed)
        : I(I), C(C), X(X), seed(seed), NC(int(I.rows.size())), twoD(I.dim == 2), dt(dt), dmin(dmin),
          xi(I.settings.tolerance * dmin), xi2(xi * xi), dt2(dt * dt), cs(I.rows.data()),
          bodies(I.body.data()), adjS(I.adjStart.data()), adjI(I.adjItems.data()),
          maxSolves(long(I.settings.maxIterations) * long(std::max(NC, 1)))
    {
    }

    void run(StepReport& rep)
    {
        queueRows();
        flagInterfaceRows();
        bool busy = true;
        bool capped = false; // some subdomain reached maxSolves (global)
        for (;;)
        {
            while (busy && !capped && averagings < I.settings.maxIterations)
            {
                sweep(); // one sweep-equivalent of local solves (or the queue emptied)
                averageInterface(I, C, X,
                                 [&](int s, double du)
                                 {
                                     if (du * dt > requeueFraction * xi) pushBody(s);
                                 });
                ++averagings;
                double flags[2] = {Q.count > 0 ? 1.0 : 0.0, solves >= maxSolves ? 1.0 : 0.0};
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
            for (int k : X.ifaceRows)
                if (rowResidual2(k) > xi2) Q.push(k);
            busy = C.maxOverSubdomains(Q.count > 0 ? 1.0 : 0.0) > 0;
            if (!busy) break;
        }
        const double res = C.maxOverSubdomains(std::sqrt(residual2AndFinish()));
        rep.contacts = std::max(rep.contacts, NC);
        rep.localSolves += solves;
        rep.sweeps += NC > 0 ? int((solves + NC - 1) / NC) : 0;
        rep.residual = std::max(rep.residual, dmin > 0 ? res / dmin : 0.0);
        rep.converged = rep.converged && !busy && !capped && res <= xi;
    }

private:
    System::Impl& I;
    SubdomainCoupling& C;
    Subdomain::Scratch& X;
    const std::vector<int>* const seed;
    const int NC;
    const bool twoD;
    const bool anitescu = I.settings.frictionLaw == System::Settings::FrictionLaw::Anitescu;
    const double dt, dmin, xi, xi2, dt2;
    SolverContact* const cs;
    Body* const bodies;
    const int* const adjS;
    const int* const adjI;
    const long maxSolves;
    RowQueue Q{nullptr, nullptr, 0};
    long solves = 0;
    int averagings = 0;

    void pushBody(int b)
    {
        for (int p = adjS[b]; p < adjS[b + 1]; ++p) Q.push(adjI[p]);
    }

    /// The 2D scalar tangential impulses (a seeded solve keeps those of the
    /// solve it continues), and the queue: the seed, or every row.
    void queueRows()
    {
        if (twoD && !I.rowsHaveRts && !seed)
            for (int k = 0; k < NC; ++k) cs[k].rts = cs[k].rt.dot(Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0));
        I.rowsHaveRts = false;
        I.queue.resize(std::max(NC, 1));
        I.inQueue.assign(NC, 0);
        Q = RowQueue{I.queue.data(), I.inQueue.data(), NC};
        if (seed)
            for (int k : *seed) Q.push(k);
        else
            for (int k = 0; k < NC; ++k) Q.push(k);
        // the rows a seeded solve solves (the others keep their change, already
        // a square root, and are not visited again)
        I.seedSolved.clear();
        if (seed) I.seedSolvedFlag.assign(NC, 0);
    }

    /// The rows of the interface grains and of the droplets with mass: the
    /// averagings move their velocities.
    void flagInterfaceRows()
    {
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
        for (int i : X.iface) flagRows(I.slotOf[i]);
        for (int b : X.dropletBodies) flagRows(b);
    }

    /// One sweep-equivalent of local solves from the queue (NC of them), or
    /// until it empties or the solves reach maxSolves.
    void sweep()
    {
        RowQueue q = Q; // (a local copy: its counters stay in registers)
        std::vector<int>& solved = I.seedSolved;
        std::vector<char>& solvedFlag = I.seedSolvedFlag;
        for (long budget = std::max(NC, 1); q.count > 0 && solves < maxSolves && budget > 0; --budget)
        {
            const int k = q.queue[q.head];
            q.head = q.head + 1 == NC ? 0 : q.head + 1;
            --q.count;
            // the rows and bodies ahead in the queue (as the undecomposed
            // NLGS, ContactSolver.cpp: a hint, results unchanged)
            if (q.count > rowsAhead) prefetch(cs + q.at(rowsAhead), sizeof(SolverContact));
            if (q.count > bodiesAhead)
            {
                const SolverContact& a = cs[q.at(bodiesAhead)];
                prefetch(bodies + a.i, sizeof(Body));
                prefetch(bodies + a.j, sizeof(Body));
            }
            q.inQ[k] = 0;
            ++solves;
            if (seed && !solvedFlag[k])
            {
                solvedFlag[k] = 1;
                solved.push_back(k);
            }
            SolverContact& c = cs[k];
            const bool changed = twoD ? local::update2D(c, bodies[c.i], bodies[c.j], dt2, xi2, 1.0, anitescu)
                                      : local::update3D(c, bodies[c.i], bodies[c.j], dt2, xi2, 1.0, anitescu);
            if (!changed) continue;
            q.push(k);
            for (int b : {c.i, c.j})
                for (int p = adjS[b]; p < adjS[b + 1]; ++p) q.push(adjI[p]);
        }
        Q = q;
    }

    /// Residual (ContactSolver.cpp), squared, of row k at the current velocities.
    double rowResidual2(int k) const
    {
        const SolverContact& c = cs[k];
        const Vec3 rt = twoD ? Vec3(c.rts * Vec3(-c.n.y(), c.n.x(), 0.0)) : c.rt;
        return localResidual2(c, rt, bodies[c.i], bodies[c.j], dt, anitescu);
    }

    /// The residual, squared: the last change of each row solved, evaluated
    /// at the current velocities for the rows of interface grains. In the
    /// same pass the rows are finished (2D tangential impulse back to a
    /// vector, change to its square root: one pass over the rows, which are
    /// memory-bound), once, when the solve stops.
    double residual2AndFinish()
    {
        double r = 0;
        auto finishRow = [&](int k)
        {
            SolverContact& c = cs[k];
            if (!X.ifaceRow[k]) r = std::max(r, c.change);
            if (twoD) c.rt = c.rts * Vec3(-c.n.y(), c.n.x(), 0.0);
            c.change = std::sqrt(c.change);
        };
        if (seed)
            for (int k : I.seedSolved) finishRow(k);
        else
            for (int k = 0; k < NC; ++k) finishRow(k);
        for (int k : X.ifaceRows) r = std::max(r, rowResidual2(k));
        return r;
    }
};
} // namespace

void solveDecomposed(System::Impl& I, SubdomainCoupling& C, Subdomain::Scratch& X, double dt, double dmin,
                     StepReport& rep, const std::vector<int>* seed)
{
    InterfaceSolve(I, C, X, dt, dmin, seed).run(rep);
}

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

} // namespace nscd
