// The contact solve of System::step on the rows prepared by prepareContacts:
// nonlinear Gauss-Seidel with contact queue (NLGS, optionally over-relaxed)
// and the residual shared by every method (APGD: ContactSolverAPGD.cpp, NNCG:
// ContactSolverNNCG.cpp; the local solve: LocalSolve.H).
#include "LocalSolve.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

using local::projectNormal;
using local::projectTangent;

double localResidual2(const SolverContact& c, const Vec3& rt, const Body& A, const Body& B, double dt)
{
    const Vec3& n = c.n;
    const Vec3 du = A.v - B.v - (A.r*A.w + B.r*B.w).cross(n);
    const double un = du.dot(n);
    const double unFree = un - c.wnn*c.rn + c.bias;
    const Vec3 utFree = (du - un*n) - c.wtt*rt;
    const double rn = projectNormal(-unFree*c.iwnn, c);
    const double rnt = rn + c.coh;
    Vec3 rtNew = Vec3::Zero();
    if (rnt > 0.0)
    {
        rtNew = utFree*(-c.iwtt);
        projectTangent(rtNew, c.mu*rnt);
    }
    const double dn = rn - c.rn;
    return (c.wnn*c.wnn*dn*dn + c.wtt*c.wtt*(rtNew - rt).squaredNorm())*dt*dt*c.residualWeight2;
}

double System::Impl::residualPass(double dt, bool scalarTangent) const
{
    double res = 0;
    for (const SolverContact& c : rows)
    {
        const Vec3 rt = scalarTangent ? Vec3(c.rts*Vec3(-c.n.y(), c.n.x(), 0.0)) : c.rt;
        res = std::max(res, localResidual2(c, rt, body[c.i], body[c.j], dt));
    }
    return res;
}

void System::Impl::solveContacts(double dt, StepReport& rep, const std::vector<int>* seed)
{
    const Settings::Method m = settings.method;
    rep.method = int(m);
    const bool haveRts = rowsHaveRts;  // for this solve only (NLGS)
    rowsHaveRts = false;
    if (m == Settings::Method::APGD) { solveAPGD(dt, rep); return; }
    if (m == Settings::Method::NNCG) { solveNNCG(dt, rep); return; }
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
    const double dt, omega;
    const bool twoD = I.dim == 2;
    const double dmin = 2*I.rMin();
    const int NC = int(I.rows.size());
    const bool hist = I.settings.residualHistory;
    const double xi = I.settings.tolerance*dmin;
    const long maxSolves = long(I.settings.maxIterations)*long(std::max(NC, 1));
    const double xi2 = xi*xi, dt2 = dt*dt;
    Body* const bodies = I.body.data();
    SolverContact* const cs = I.rows.data();
    const int* const adjS = I.adjStart.data();
    const int* const adjI = I.adjItems.data();
    char* inQ = nullptr;
    const std::vector<int>* seed = nullptr;  ///< rows queued at the start (null: all)
    long solves = 0;  ///< local solves so far
    int count = 0;    ///< rows in the queue

    NlgsSolve(System::Impl& impl, StepReport& r, double dtStep, double omegaStep)
    : I(impl), rep(r), dt(dtStep), omega(omegaStep) {}

    /// Residual [-] (residualPass) for residualHistory.
    double historyEntry(bool scalarTangent) const
    { return dmin > 0 ? std::sqrt(I.residualPass(dt, scalarTangent))/dmin : 0.0; }

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
            for (int k = 0; k < NC; ++k)
                cs[k].rts = cs[k].rt.dot(Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0));
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
        ++solves;
        if (seed && !I.seedSolvedFlag[k]) { I.seedSolvedFlag[k] = 1; I.seedSolved.push_back(k); }
        SolverContact& c = cs[k];
        const bool changed = twoD ? local::update2D(c, bodies[c.i], bodies[c.j], dt2, xi2, omega)
                                  : local::update3D(c, bodies[c.i], bodies[c.j], dt2, xi2, omega);
        if (hist && solves % NC == 0) rep.residualHistory.push_back(historyEntry(twoD));
        return changed;
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
    void prefetchAhead(const int* queue, int head) const
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
        }
    }

    /// FIFO contact queue (section 2.3): a non-converged contact and the
    /// contacts sharing its bodies are (re-)appended to the queue.
    void fifo()
    {
        I.queue.resize(NC);
        if (seed) std::copy(seed->begin(), seed->end(), I.queue.begin());
        else for (int k = 0; k < NC; ++k) I.queue[k] = k;
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
        while (count > 0 && solves < maxSolves)
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
        auto mark = [&](int kk) { if (!inQ[kk]) { inQ[kk] = 1; ++count; } };
        int lo = 0, hi = NC - 1;  // range that may contain flagged contacts
        bool forward = true;
        while (count > 0 && solves < maxSolves)
        {
            int nlo = NC, nhi = -1;
            auto visit = [&](int k)
            {
                if (!inQ[k]) return;
                inQ[k] = 0;
                --count;
                if (!solveOne(k)) return;
                mark(k);
                nlo = std::min(nlo, k); nhi = std::max(nhi, k);
                const SolverContact& c = cs[k];
                for (int p = adjS[c.i]; p < adjS[c.i + 1]; ++p)
                { const int kk = adjI[p]; mark(kk); nlo = std::min(nlo, kk); nhi = std::max(nhi, kk); }
                for (int p = adjS[c.j]; p < adjS[c.j + 1]; ++p)
                { const int kk = adjI[p]; mark(kk); nlo = std::min(nlo, kk); nhi = std::max(nhi, kk); }
            };
            if (forward) for (int k = lo; k <= hi && solves < maxSolves; ++k) visit(k);
            else for (int k = hi; k >= lo && solves < maxSolves; --k) visit(k);
            lo = nlo; hi = nhi;
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
            if (twoD) c.rt = c.rts*Vec3(-c.n.y(), c.n.x(), 0.0);
            if (count == 0) res = std::max(res, c.change);
            c.change = std::sqrt(c.change);
        };
        if (seed) for (int k : I.seedSolved) finishRow(cs[k]);
        else for (int k = 0; k < NC; ++k) finishRow(cs[k]);
        if (count != 0) res = I.residualPass(dt, false);  // (does not read change)
        res = std::sqrt(res);
        if (hist && (rep.residualHistory.empty() || solves % std::max(NC, 1) != 0))
            rep.residualHistory.push_back(dmin > 0 ? res/dmin : 0.0);
        rep.contacts = NC;
        rep.localSolves = solves;
        rep.sweeps = NC > 0 ? int((solves + NC - 1)/NC) : 0;
        rep.residual = dmin > 0 ? res/dmin : 0;
        rep.converged = count == 0;
    }
};

} // namespace

void System::Impl::solveNLGS(double dt, double omega, StepReport& rep, bool haveRts,
                               const std::vector<int>* seed)
{
    // ---- nonlinear Gauss-Seidel with contact queue (Algorithm 2, section 2.3) ----
    NlgsSolve s(*this, rep, dt, omega);
    s.start(haveRts, seed);
    if (settings.ordering == Settings::Ordering::Fifo) s.fifo();
    else s.symmetric();
    s.finish();
}

} // namespace nscd
