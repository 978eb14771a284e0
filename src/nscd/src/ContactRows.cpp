// SPDX-License-Identifier: GPL-3.0-or-later
// The solver rows of a step (System::step, Step.cpp): built from the
// detected contacts by prepareContacts (Delassus diagonal, contact law,
// age, cohesion, warm start, adjacency counts), the adjacency of the
// movable bodies, and the rows written back into the persistent contact
// records by storeImpulses.
// The warm start and the adjacency counts are applied row by row inside
// prepareContacts (one pass over the rows instead of three: at 70,000 discs
// at rest the passes over the contact arrays are memory-bound).
#include "ContactLaws.H"
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

namespace
{
/// Largest residual weight k of a contact (SolverContact::residualWeight2)
constexpr double maxResidualWeight = 1e3;

/// prepareContacts prefetches the bodies of the row this far ahead
/// (the bodies are visited out of memory order; results unchanged).
constexpr int bodiesAhead = 8;

/// Row s of contact c between bodies A and B: its bodies, normal, friction
/// and cap, the diagonal of its local Delassus operator W (W_nn, W_tt,
/// their inverses, the residual weight), impulses and change zero.
inline void startRow(SolverContact& s, const Contact& c, const Body& A, const Body& B)
{
    s.i = c.i;
    s.j = c.j;
    s.n = c.n;
    s.mu = c.mu;
    s.cap = c.cap;
    s.wnn = A.im + B.im;
    s.wtt = A.im + B.im + A.r * A.r * A.ii + B.r * B.r * B.ii;
    s.iwnn = s.wnn > 0 ? 1.0 / s.wnn : 0.0;
    s.iwtt = s.wtt > 0 ? 1.0 / s.wtt : 0.0;
    // capped: a grain with c dt/m beyond the cap is locked to its fluid
    // velocity (e.g. eps clipped at epsMin), its velocity, not its drag, is
    // what matters, and round-off would stall the test
    const double k = s.wnn > 0 ? std::min((A.im0 + B.im0) / s.wnn, maxResidualWeight) : 1.0;
    s.residualWeight2 = k * k;
    s.rn = 0;
    s.rt.setZero();
    s.change = 0;
    s.coh = 0;
}

/// The regularisation eps of contact c (Material::compliance,
/// relativeCompliance of its slots' materials, slotCompliance) with normal
/// diagonal wnn; 0: the hard law.
inline double compliantEps(const std::vector<std::array<double, 2>>& slotCompliance, const Contact& c, int N,
                           double wnn, double idt2, double ratio2)
{
    return law::CompliantSignorini::contactRegularisation(
        slotCompliance[c.i], c.j < N ? &slotCompliance[c.j] : nullptr, wnn, idt2, ratio2);
}

/// The same contact as c in the previous step's records P: same bodies,
/// normal within 60 degrees; -1 if none. P is sorted by i, and so are the
/// rows (detect) up to the droplet rows: the cursor pLo walks P along with
/// the rows (no separate pass over P to index it), restarted by a binary
/// search when i decreases (lastI: the i of the row before).
inline int previousContact(const std::vector<Contact>& P, const Contact& c, int& pLo, int& lastI)
{
    const int NP = int(P.size());
    if (c.i < lastI)
        pLo = int(std::lower_bound(P.begin(), P.end(), c.i, [](const Contact& a, int i) { return a.i < i; })
                  - P.begin());
    else
        while (pLo < NP && P[pLo].i < c.i) ++pLo;
    lastI = c.i;
    int best = -1;
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
    return best;
}

/// The warm-start impulse of row s (contact c): the impulse of the same
/// contact p in the previous step times scale (dt/lastDt), in the row's
/// frame and Coulomb cone (with its cohesion).
inline void warmImpulse(SolverContact& s, const Contact& c, const Contact& p, double scale)
{
    const Vec3 imp = scale * (p.rn * p.n + p.rt);
    s.rn = std::max(-s.coh, imp.dot(c.n));
    s.rt = imp - imp.dot(c.n) * c.n;
    const double lim = s.mu * (s.rn + s.coh);
    const double tn = s.rt.norm();
    if (tn > lim) s.rt *= (tn > 0 ? lim / tn : 0.0);
}
} // namespace

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
    int pLo = 0, lastI = -1; // the cursor of previousContact
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
    // relativeCompliance's step T (complianceDt, set over the sub-steps of
    // advance()): beta W_nn T^2 is the spring of the step asked for, whatever
    // its sub-steps. With T = dt each sub-step would stiffen the law by n^2:
    // a loaded bed's overlaps, past the new equilibrium, pushed out at
    // overlap/dt in one sub-step, added up over the layers (measured: grains
    // launched at 1.6-49 m/s from 360-layer settling beds), and the push
    // raising the sub-step count further.
    const double T = lawStep(dt), ratio2 = (T / dt) * (T / dt);
    for (int k = 0; k < NC; ++k)
    {
        if (k + bodiesAhead < NC) // the bodies of a later row (random access: a hint)
        {
            prefetch(&body[C[k + bodiesAhead].i], sizeof(Body));
            prefetch(&body[C[k + bodiesAhead].j], sizeof(Body));
        }
        Contact& c = C[k];
        SolverContact& s = rows[k];
        startRow(s, c, body[c.i], body[c.j]);
        // the contact's law (ContactLaws.H): compliant if its materials
        // have a compliance (the normal diagonal W_nn + eps; its gap term
        // after the warm start, below), else the hard law with the slop band
        // and push-out (droplet rows k >= NC0: the hard law exactly)
        const double eps =
            compliant && k < NC0 ? compliantEps(slotCompliance, c, N, s.wnn, idt2, ratio2) : 0.0;
        if (eps > 0)
            s.iwnn = 1.0 / (s.wnn + eps);
        else
        {
            s.bias = law::HardSignorini::bias(c.gap, dt, slop, k < NC0);
            if (k < NC0 && law::HardSignorini::pushesOut(s.bias)) relaxSeed.push_back(k); // relaxPushOut
        }
        // the same contact in the previous step (its age, its warm start)
        const int best = match ? previousContact(P, c, pLo, lastI) : -1;
        c.age = best >= 0 ? P[best].age : 0;
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
            warmImpulse(s, c, P[best], scale);
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

// ---- impulses into the persistent records, age (closed: loaded or touching) ----
void System::Impl::storeImpulses(double dt, int NC0, StepReport& rep)
{
    const double xi = settings.tolerance * (2 * rMin()); // as the solver's xi
    std::vector<Contact>& C = newContacts;
    lastDt = dt;
    lastComplianceDt = lawStep(dt);
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
