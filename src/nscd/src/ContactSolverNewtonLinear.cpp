// SPDX-License-Identifier: GPL-3.0-or-later
// The Newton contact solve's matrix and linear solve (System::Settings::
// Method::Newton; the method: ContactSolverNewton.cpp): the sparse pattern
// of H = M + sum_k J_k^T B_k J_k (lower triangle), kept with its LDLT
// ordering from step to step in a per-thread cache, filled in place, and
// solved by SimplicialLDLT or incomplete-Cholesky CG.
#include "ContactSolverNewtonImpl.H"

#include <Eigen/SparseCholesky>

#include <algorithm>

namespace nscd
{
namespace newton
{

/**
 * The matrix pattern of the last solve on this thread, kept for the next:
 * the contacts of a bed at rest change little from step to step, and when
 * every row touches the same unknowns as before, the pattern of H, the
 * positions of the rows' entries and the LDLT's ordering and symbolic
 * analysis are reused. key lists nv and each row's unknowns.
 */
struct PatternCache
{
    std::vector<int> key; ///< nv, then per row: -1 (skipped) or ncol and its col[0..ncol)
    SpMat H;              ///< the pattern of key (values: the last solve's, reset before use)
    std::vector<int> diagSlot, slotStart, slots;     ///< NewtonSolve's positions in H's values
    Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt; ///< the LDLT's ordering and analysis (and last factor)
    bool analysed = false;                           ///< ldlt's analyzePattern done for H's pattern
};

/**
 * @brief The Newton solve's pattern cache, one per thread.
 *
 * What it caches: H's sparsity pattern (lower triangle of M + sum_k J_k^T
 * J_k), the positions in H's values of M's diagonal (diagSlot) and of each
 * row's block entries (slotStart, slots), and the SimplicialLDLT's fill-
 * reducing ordering and symbolic analysis of that pattern (with the last
 * numeric factor, overwritten by the next factorize).
 *
 * When it is invalidated: at the start of every solve, NewtonSolve::
 * buildPattern builds the key (nv, then each row's unknowns in order: -1 for
 * a skipped row, else ncol and col[0..ncol)) and compares it with key; on
 * any difference the pattern and the positions are rebuilt and analysed is
 * cleared, so that the first LDLT solve analyses the pattern again. The key
 * is cleared while the pattern is rebuilt, so that an exception there (e.g.
 * bad_alloc) cannot leave a key naming a pattern it does not hold.
 *
 * Why thread_local: the Newton solve is a step's (System::Impl::
 * solveNewton) and may run on several threads at once (separate Systems,
 * e.g. one per thread); a per-thread cache needs no lock and no storage in
 * System or in its public header, and one thread stepping one System hits
 * it at every step whose contacts touch the same unknowns (a bed at rest).
 *
 * Limits, and why it never changes results: the cache is shared by every
 * System stepped on the thread. Two Systems stepping alternately on one
 * thread (or a System whose rows change) rebuild it at each solve whose key
 * differs from the last one: a pattern build and an analyzePattern more,
 * a performance loss only. Everything cached is a function of the key
 * alone: the pattern is built from nv and the rows' columns only, the
 * positions from the pattern and the columns, and the LDLT's ordering and
 * symbolic analysis from the pattern only (deterministic); the values of H
 * are all reset (resetHessian) and the LDLT factorized again before every
 * linear solve. So a hit, even by another System with the same key, gives
 * the bit-identical matrix, ordering and factor of a rebuild, and results
 * do not depend on what ran on the thread before. Its memory (the last
 * pattern, factor and positions) is kept until the thread ends. The CG
 * solver (Settings::NewtonLinearSolver::ConjugateGradient) uses the pattern
 * and positions but not the LDLT; its preconditioner is computed at each
 * solve.
 */
thread_local PatternCache patternCache;

NewtonSolve::NewtonSolve(System::Impl& impl, double dtStep)
    : I(impl), dt(dtStep), m(impl.dim == 2 ? 2 : 3), NC(int(impl.rows.size())), cache(patternCache),
      H(patternCache.H), diagSlot(patternCache.diagSlot), slotStart(patternCache.slotStart),
      slots(patternCache.slots)
{
}

void NewtonSolve::buildPattern()
{
    std::vector<int> key{nv};
    key.reserve(1 + 7 * NC);
    for (const NewtonRow& r : R)
    {
        key.push_back(r.skip ? -1 : r.ncol);
        if (!r.skip) key.insert(key.end(), r.col, r.col + r.ncol);
    }
    if (key == cache.key) return; // the last solve's pattern
    cache.key.clear();            // no key while the pattern is rebuilt (see patternCache)
    cache.analysed = false;
    std::vector<Eigen::Triplet<double>> T;
    for (int i = 0; i < nv; ++i) T.emplace_back(i, i, 0.0);
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        for (int i = 0; i < r.ncol; ++i)
            for (int j = 0; j < r.ncol; ++j)
                if (r.col[i] >= r.col[j]) T.emplace_back(r.col[i], r.col[j], 0.0);
    }
    H.resize(nv, nv);
    H.setFromTriplets(T.begin(), T.end());
    H.makeCompressed();
    const double* v0 = H.valuePtr();
    diagSlot.resize(nv);
    for (int i = 0; i < nv; ++i) diagSlot[i] = int(&H.coeffRef(i, i) - v0);
    slotStart.assign(NC + 1, 0);
    slots.clear();
    for (int k = 0; k < NC; ++k)
    {
        slotStart[k] = int(slots.size());
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        for (int i = 0; i < r.ncol; ++i)
            for (int j = 0; j < r.ncol; ++j)
                slots.push_back(r.col[i] >= r.col[j] ? int(&H.coeffRef(r.col[i], r.col[j]) - v0) : -1);
    }
    slotStart[NC] = int(slots.size());
    cache.key.swap(key);
}

void NewtonSolve::resetHessian()
{
    std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
    for (int i = 0; i < nv; ++i) H.valuePtr()[diagSlot[i]] = mass(i);
}

void NewtonSolve::addBlock(int k, const Eigen::Matrix3d& B)
{
    const NewtonRow& r = R[k];
    double BJ[3][12];
    for (int a = 0; a < m; ++a)
        for (int j = 0; j < r.ncol; ++j)
        {
            double s = 0;
            for (int b = 0; b < m; ++b) s += B(a, b) * r.J[b][j];
            BJ[a][j] = s;
        }
    double* val = H.valuePtr();
    const int* slot = slots.data() + slotStart[k];
    for (int i = 0; i < r.ncol; ++i)
        for (int j = 0; j < r.ncol; ++j)
        {
            const int at = slot[i * r.ncol + j];
            if (at < 0) continue;
            double s = 0;
            for (int a = 0; a < m; ++a) s += r.J[a][i] * BJ[a][j];
            val[at] += s;
        }
}

void NewtonSolve::hessian()
{
    resetHessian();
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = R[k];
        if (r.skip) continue;
        addBlock(k, project(vc[k], r.vhatN, r.Rn, r.Rt, r.mu, true).G);
    }
}

void NewtonSolve::linearSolve(const Eigen::VectorXd& g)
{
    // the pattern of H is the same for every solve of the step
    if (useCg)
    {
        cg.setTolerance(cgTolerance);
        cg.compute(H);
        dv = cg.solve(-g);
        cgIterations += cg.iterations();
    }
    else
    {
        if (!cache.analysed)
        {
            cache.ldlt.analyzePattern(H);
            cache.analysed = true;
        }
        cache.ldlt.factorize(H);
        dv = cache.ldlt.solve(-g);
    }
}

} // namespace newton
} // namespace nscd
