// SPDX-License-Identifier: GPL-3.0-or-later
// Heat stage of the decomposed step (SubdomainHeat.H).
#include "SubdomainHeat.H"

#include <cmath>

namespace nscd
{

void decomposedHeatStep(System::Impl& I, SubdomainCoupling& C, const std::vector<char>& owned, double dt,
                        StepReport& rep)
{
    const int N = int(I.x.size());
    // rows of every local integrated grain (Heat.cpp); a ghost's own terms
    // (capacity, source, exchange) belong to its owner's row: cleared here
    const int n = I.heatUnknowns(dt);
    std::vector<char> mine(n);
    for (int a = 0; a < n; ++a)
    {
        mine[a] = owned[I.heatGrain[a]] ? 1 : 0;
        if (!mine[a])
        {
            I.hDiag[a] = 0;
            I.hR[a] = 0;
        }
    }
    I.heatGraph(dt); // this subdomain's contacts: edges to ghosts included

    // node values <-> per-grain values, for the collectives
    std::vector<double> g(N);
    auto sumToOwners = [&](std::vector<double>& u)
    {
        std::fill(g.begin(), g.end(), 0.0);
        for (int a = 0; a < n; ++a) g[I.heatGrain[a]] = u[a];
        C.sumGhostsToOwners(g);
        for (int a = 0; a < n; ++a) u[a] = mine[a] ? g[I.heatGrain[a]] : 0.0;
    };
    auto copyToGhosts = [&](std::vector<double>& u)
    {
        std::fill(g.begin(), g.end(), 0.0);
        for (int a = 0; a < n; ++a) g[I.heatGrain[a]] = u[a];
        C.copyOwnersToGhosts(g);
        for (int a = 0; a < n; ++a)
            if (!mine[a]) u[a] = g[I.heatGrain[a]];
    };
    const System::Impl::HeatDot dot = [&](const std::vector<double>& u, const std::vector<double>& v)
    {
        double s = 0;
        for (int a = 0; a < n; ++a)
            if (mine[a]) s += u[a] * v[a];
        return C.sumOverSubdomains(s);
    };
    const System::Impl::HeatProduct applyA = [&](std::vector<double>& p, std::vector<double>& y)
    {
        copyToGhosts(p);
        I.heatProduct(p, y);
        sumToOwners(y);
    };
    sumToOwners(I.hDiag); // (the ghosts' entries now 0: not rows here)
    sumToOwners(I.hR);

    // Jacobi-preconditioned conjugate gradients for the increment and the
    // flux-form update (Heat.cpp) on the owned rows, the ghosts' T* from
    // their owners and the heat rates into ghosts moved to their owners
    StepReport h;
    I.heatSolve(h, applyA, dot, mine);
    copyToGhosts(I.hX);
    I.heatUpdate(dt, h, mine, sumToOwners);
    C.copyOwnersToGhosts(I.T);
    rep.heatIterations = h.heatIterations;
    rep.heatResidual = h.heatResidual;
    rep.sourceHeat += C.sumOverSubdomains(h.sourceHeat);
    rep.exchangeHeat += C.sumOverSubdomains(h.exchangeHeat);
    rep.wallHeat += C.sumOverSubdomains(h.wallHeat);
    rep.fixedGrainHeat += C.sumOverSubdomains(h.fixedGrainHeat);
}

} // namespace nscd
