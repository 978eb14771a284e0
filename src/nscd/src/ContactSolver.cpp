// SPDX-License-Identifier: GPL-3.0-or-later
// The contact solve of System::step on the rows prepared by prepareContacts:
// nonlinear Gauss-Seidel with contact queue (NLGS, optionally over-relaxed)
// and the residual shared by every method (APGD: ContactSolverAPGD.cpp, NNCG:
// ContactSolverNNCG.cpp; the local solve: LocalSolve.H).
#include "LocalSolve.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

double localResidual2(const SolverContact& c, const Vec3& rt, const Body& A, const Body& B, double dt,
                      bool anitescu)
{
    const Vec3& n = c.n;
    const Vec3 du = A.v - B.v - (A.r * A.w + B.r * B.w).cross(n);
    const double un = du.dot(n);
    const double unFree = un - c.wnn * c.rn + c.bias;
    const Vec3 utFree = (du - un * n) - c.wtt * rt;
    double rn;
    Vec3 rtNew;
    local::localSolution3D(c, unFree, utFree, local::convexRow(c, anitescu), rn, rtNew);
    const double dn = rn - c.rn;
    return (c.wnn * c.wnn * dn * dn + c.wtt * c.wtt * (rtNew - rt).squaredNorm()) * dt * dt
           * c.residualWeight2;
}

double System::Impl::residualPass(double dt, bool scalarTangent) const
{
    const bool anitescu = settings.frictionLaw == Settings::FrictionLaw::Anitescu;
    double res = 0;
    for (const SolverContact& c : rows)
    {
        const Vec3 rt = scalarTangent ? Vec3(c.rts * Vec3(-c.n.y(), c.n.x(), 0.0)) : c.rt;
        res = std::max(res, localResidual2(c, rt, body[c.i], body[c.j], dt, anitescu));
    }
    return res;
}

void System::Impl::solveContacts(double dt, StepReport& rep, const std::vector<int>* seed)
{
    const Settings::Method m = settings.method;
    rep.method = int(m);
    const bool haveRts = rowsHaveRts; // for this solve only (NLGS)
    rowsHaveRts = false;
    if (m == Settings::Method::APGD)
    {
        solveAPGD(dt, rep);
        return;
    }
    if (m == Settings::Method::NNCG)
    {
        solveNNCG(dt, rep);
        return;
    }
    if (m == Settings::Method::Newton)
    {
        solveNewton(dt, rep);
        return;
    }
    double omega = settings.relaxation;
    if (m == Settings::Method::OverRelaxedNLGS && omega == 1.0) omega = Settings::defaultOverRelaxation;
    solveNLGS(dt, omega, rep, haveRts, seed);
}

namespace
{

/// One NLGS solve (Algorithm 2, section 2.3) on the rows of System::Impl:
/// the local update, the two queue orderings and the result, sharing the
/// counters of local solves (solves) and of rows in the queue (count).
struct NlgsSolve
{
    System::Impl& I;
    StepReport& rep;
    const double dt;
    /// over-relaxation factor: set to 1 once solves reach fallbackSolves
    double omega;
    const bool twoD = I.dim == 2;
    const bool anitescu = I.settings.frictionLaw == System::Settings::FrictionLaw::Anitescu;
    const double dmin = 2 * I.rMin();
    const int NC = int(I.rows.size());
    const bool hist = I.settings.residualHistory;
    const double xi = I.settings.tolerance * dmin;
    const long maxSolves = long(I.settings.maxIterations) * long(std::max(NC, 1));
    /// an over-relaxed solve not converged after half of the cap goes on
    /// with plain Gauss-Seidel (Settings::relaxation)
    const long fallbackSolves = maxSolves / 2;
    const double dt2 = dt * dt;
    /// squared threshold of a row's update below which it is converged:
    /// Max test xi^2; RMS test (rmsTolerance V dt)^2, updated every pass
    double xi2 = xi * xi;
    // ---- Settings::Convergence::RMS (LMGC90's Quad norm) ----
    const bool rms = I.settings.convergence == System::Settings::Convergence::RMS;
    const double rmsTol2 = I.settings.rmsTolerance * I.settings.rmsTolerance;
    /// the pass test's safeguard: no update of the pass above 10 rmsTolerance V
    static constexpr double rmsSafeguard2 = 100;
    /// floor of the RMS threshold (no impulse yet: V = 0): round-off of d_min
    const double rmsFloor2 = 1e-24 * dmin * dmin;
    double refSum = 0;       ///< sum_k |W_kk r_k|^2 dt^2 k^2 (V^2 NC dt^2, as change)
    double passSum = 0;      ///< sum of the squared updates of the current pass
    double passMax = 0;      ///< largest squared update of the current pass
    double lastPassMax = 0;  ///< passMax of the pass that met the test
    bool rmsStopped = false; ///< the RMS test was met at the end of a pass
    Body* const bodies = I.body.data();
    SolverContact* const cs = I.rows.data();
    const int* const adjS = I.adjStart.data();
    const int* const adjI = I.adjItems.data();
    char* inQ = nullptr;
    const std::vector<int>* seed = nullptr; ///< rows queued at the start (null: all)
    long solves = 0;                        ///< local solves so far
    int count = 0;                          ///< rows in the queue

    NlgsSolve(System::Impl& impl, StepReport& r, double dtStep, double omegaStep)
        : I(impl), rep(r), dt(dtStep), omega(omegaStep)
    {
    }

    /// Residual [-] (residualPass) for residualHistory.
    double historyEntry(bool scalarTangent) const
    {
        return dmin > 0 ? std::sqrt(I.residualPass(dt, scalarTangent)) / dmin : 0.0;
    }

    /// Initial residual, 2D scalar tangential impulses (unless haveRts:
    /// prepareContacts has set them), every row queued, or only the rows
    /// of seedRows: the others are converged (their change, the square
    /// root left by the last finish(), is squared again for the residual).
    void start(bool haveRts, const std::vector<int>* seedRows)
    {
        if (hist) rep.residualHistory.push_back(historyEntry(false));
        // 2D: scalar tangential impulse along t = z x n (same law, fewer flops;
        // a seeded solve continues a solve whose rts are kept)
        if (twoD && !haveRts && !seedRows)
            for (int k = 0; k < NC; ++k) cs[k].rts = cs[k].rt.dot(Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0));
        if (rms)
        {
            for (int k = 0; k < NC; ++k) refSum += ref2(cs[k]);
            xi2 = std::max(rmsTol2 * refSum / std::max(NC, 1), rmsFloor2);
        }
        seed = seedRows;
        I.inQueue.assign(NC, seed ? 0 : 1);
        inQ = I.inQueue.data();
        count = NC;
        if (!seed) return;
        for (int k : *seed) inQ[k] = 1;
        count = int(seed->size());
        I.seedSolved.clear();
        I.seedSolvedFlag.assign(NC, 0);
    }

    /// One local update of row k (Algorithm 2 body), then the residual
    /// history every NC solves; returns true if the row had not converged
    /// (its impulse was changed), false if |W dr| dt < xi (the previous
    /// impulse is kept, as in Algorithm 2).
    bool solveOne(int k)
    {
        if (++solves > fallbackSolves && omega != 1.0)
        {
            omega = 1.0;
            ++rep.relaxationFallbacks;
        }
        if (seed && !I.seedSolvedFlag[k])
        {
            I.seedSolvedFlag[k] = 1;
            I.seedSolved.push_back(k);
        }
        SolverContact& c = cs[k];
        const double before = rms ? ref2(c) : 0.0;
        const bool changed = twoD ? local::update2D(c, bodies[c.i], bodies[c.j], dt2, xi2, omega, anitescu)
                                  : local::update3D(c, bodies[c.i], bodies[c.j], dt2, xi2, omega, anitescu);
        if (hist && solves % NC == 0) rep.residualHistory.push_back(historyEntry(twoD));
        if (rms)
        {
            refSum += ref2(c) - before;
            passSum += c.change;
            passMax = std::max(passMax, c.change);
            if (solves % NC == 0) endPass();
        }
        return changed;
    }

    /// |W_kk r_k|^2 dt^2 k^2 of row c (the RMS test's reference, in the
    /// units of SolverContact::change): the velocity its own impulse makes.
    double ref2(const SolverContact& c) const
    {
        const double t2 = twoD ? c.rts * c.rts : c.rt.squaredNorm();
        return (c.wnn * c.wnn * c.rn * c.rn + c.wtt * c.wtt * t2) * dt2 * c.residualWeight2;
    }

    /// RMS test at the end of a pass of NC local solves (Settings::convergence):
    /// met if the pass's RMS update is <= rmsTolerance V and none of its
    /// updates exceeds 10 rmsTolerance V; the row threshold follows V.
    void endPass()
    {
        const double v2 = std::max(refSum, 0.0) / NC; // V^2 dt^2 (incremental sum: no sign drift below 0)
        if (passSum / NC <= rmsTol2 * v2 && passMax <= rmsSafeguard2 * rmsTol2 * v2)
        {
            rmsStopped = true;
            lastPassMax = passMax;
            rep.rmsResidual = v2 > 0 ? std::sqrt(passSum / NC / v2) : 0.0;
        }
        xi2 = std::max(rmsTol2 * v2, rmsFloor2);
        passSum = passMax = 0;
    }

    /// Rows this far ahead in the queue are prefetched, and the bodies of
    /// the rows half as far ahead (their row is in cache by then): after the
    /// first sweep the queue visits rows and bodies out of memory order, and
    /// the solve waits on their cache misses (perf: the loads of c.i and of
    /// the body velocities). A hint only: the results are unchanged.
    static constexpr int rowsAhead = 16, bodiesAhead = 8;

    /// Prefetch for the FIFO queue whose next row is queue[head] (count
    /// rows queued). Always inlined (see prefetch, SystemImpl.H: GCC drops calls
    /// of a function that only prefetches).
#if defined(__GNUC__)
    __attribute__((always_inline))
#endif
    void
    prefetchAhead(const int* queue, int head) const
    {
        if (count > rowsAhead)
        {
            const int h = head + rowsAhead;
            prefetch(cs + queue[h >= NC ? h - NC : h], sizeof(SolverContact));
        }
        if (count > bodiesAhead)
        {
            const int h = head + bodiesAhead;
            const SolverContact& c = cs[queue[h >= NC ? h - NC : h]];
            prefetch(bodies + c.i, sizeof(Body));
            prefetch(bodies + c.j, sizeof(Body));
            // the rows sharing its bodies, which a changed row pushes
            // (perf: the loads of adjItems were 2/3 of the queue's own time)
            prefetch(adjI + adjS[c.i], sizeof(int));
            prefetch(adjI + adjS[c.j], sizeof(int));
        }
    }

    /// FIFO contact queue (section 2.3): a non-converged contact and the
    /// contacts sharing its bodies are (re-)appended to the queue.
    void fifo()
    {
        I.queue.resize(NC);
        if (seed)
            std::copy(seed->begin(), seed->end(), I.queue.begin());
        else
            for (int k = 0; k < NC; ++k) I.queue[k] = k;
        int head = 0;
        int* queue = I.queue.data();
        auto push = [&](int kk)
        {
            if (inQ[kk]) return;
            inQ[kk] = 1;
            int tail = head + count;
            if (tail >= NC) tail -= NC;
            queue[tail] = kk;
            ++count;
        };
        while (count > 0 && solves < maxSolves && !rmsStopped)
        {
            const int k = queue[head];
            head = (head + 1 == NC) ? 0 : head + 1;
            --count;
            prefetchAhead(queue, head);
            inQ[k] = 0;
            if (!solveOne(k)) continue;
            push(k);
            const SolverContact& c = cs[k];
            for (int p = adjS[c.i]; p < adjS[c.i + 1]; ++p) push(adjI[p]);
            for (int p = adjS[c.j]; p < adjS[c.j + 1]; ++p) push(adjI[p]);
        }
    }

    /// Same queue as a flag set, traversed in alternating (symmetric)
    /// sweeps: forward then backward over the contact list (sorted by grain).
    /// Only flagged contacts are solved; a non-converged contact flags
    /// itself and the contacts sharing its bodies. Alternating directions
    /// propagate forces through deep piles in both directions.
    void symmetric()
    {
        auto mark = [&](int kk)
        {
            if (!inQ[kk])
            {
                inQ[kk] = 1;
                ++count;
            }
        };
        int lo = 0, hi = NC - 1; // range that may contain flagged contacts
        bool forward = true;
        while (count > 0 && solves < maxSolves && !rmsStopped)
        {
            int nlo = NC, nhi = -1;
            auto visit = [&](int k)
            {
                if (!inQ[k]) return;
                inQ[k] = 0;
                --count;
                if (!solveOne(k)) return;
                mark(k);
                nlo = std::min(nlo, k);
                nhi = std::max(nhi, k);
                const SolverContact& c = cs[k];
                for (int p = adjS[c.i]; p < adjS[c.i + 1]; ++p)
                {
                    const int kk = adjI[p];
                    mark(kk);
                    nlo = std::min(nlo, kk);
                    nhi = std::max(nhi, kk);
                }
                for (int p = adjS[c.j]; p < adjS[c.j + 1]; ++p)
                {
                    const int kk = adjI[p];
                    mark(kk);
                    nlo = std::min(nlo, kk);
                    nhi = std::max(nhi, kk);
                }
            };
            if (forward)
                for (int k = lo; k <= hi && solves < maxSolves && !rmsStopped; ++k) visit(k);
            else
                for (int k = hi; k >= lo && solves < maxSolves && !rmsStopped; --k) visit(k);
            lo = nlo;
            hi = nhi;
            forward = !forward;
        }
    }

    /// 2D tangential impulses back to vectors, the residual and the report.
    void finish()
    {
        // The residual (the same for every method): max over contacts of the
        // plain local update |W dr| dt at the final velocities. When the queue is
        // empty, every contact was last solved after the last change of its
        // bodies' velocities and not changed then: its last change is this
        // residual. Otherwise (maxIterations hit) it is evaluated.
        // (one pass over the rows when converged: the passes over the
        // contact arrays are memory-bound)
        // A seeded solve visits only the rows it solved: the others keep
        // their tangential impulse and their change (already a square root)
        // from the solve it continues, whose residual bounds theirs.
        double res = 0;
        auto finishRow = [&](SolverContact& c)
        {
            if (twoD) c.rt = c.rts * Vec3(-c.n.y(), c.n.x(), 0.0);
            if (count == 0) res = std::max(res, c.change);
            c.change = std::sqrt(c.change);
        };
        if (seed)
            for (int k : I.seedSolved) finishRow(cs[k]);
        else
            for (int k = 0; k < NC; ++k) finishRow(cs[k]);
        // RMS test met with rows still queued: the largest update of the
        // last pass stands for the max residual (no extra pass)
        if (rmsStopped && count != 0)
            res = lastPassMax;
        else if (count != 0)
            res = I.residualPass(dt, false); // (does not read change)
        // queue emptied under the RMS test: every row's last update is below
        // rmsTolerance V, the RMS of the rows' last updates is the residual
        if (rms && !rmsStopped && count == 0 && NC > 0)
        {
            double sum = 0, ref = 0;
            for (int k = 0; k < NC; ++k)
            {
                sum += cs[k].change * cs[k].change;
                ref += ref2(cs[k]);
            }
            rep.rmsResidual = ref > 0 ? std::sqrt(sum / ref) : 0.0;
        }
        res = std::sqrt(res);
        if (hist && (rep.residualHistory.empty() || solves % std::max(NC, 1) != 0))
            rep.residualHistory.push_back(dmin > 0 ? res / dmin : 0.0);
        rep.contacts = NC;
        rep.localSolves = solves;
        rep.sweeps = NC > 0 ? int((solves + NC - 1) / NC) : 0;
        rep.residual = dmin > 0 ? res / dmin : 0;
        rep.converged = count == 0 || rmsStopped;
    }
};

} // namespace

void System::Impl::solveNLGS(double dt, double omega, StepReport& rep, bool haveRts,
                             const std::vector<int>* seed)
{
    // ---- nonlinear Gauss-Seidel with contact queue (Algorithm 2, section 2.3) ----
    NlgsSolve s(*this, rep, dt, omega);
    s.start(haveRts, seed);
    if (settings.ordering == Settings::Ordering::Fifo)
        s.fifo();
    else
        s.symmetric();
    s.finish();
}

} // namespace nscd
