// Heat stage of the decomposed step (SubdomainHeat.H).
#include "SubdomainHeat.H"

#include <cmath>

namespace nscd
{

using HeatEdge = System::Impl::HeatEdge;
using HeatBoundary = System::Impl::HeatBoundary;

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
        if (!mine[a]) { I.hDiag[a] = 0; I.hR[a] = 0; }
    }
    I.heatGraph(dt);  // this subdomain's contacts: edges to ghosts included

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
            if (mine[a]) s += u[a]*v[a];
        return C.sumOverSubdomains(s);
    };
    const System::Impl::HeatProduct applyA = [&](std::vector<double>& p, std::vector<double>& y)
    {
        copyToGhosts(p);
        for (int a = 0; a < n; ++a) y[a] = mine[a] ? I.hDiag[a]*p[a] : 0.0;
        for (const HeatEdge& e : I.heatEdges)
        {
            y[e.a] -= e.H*p[e.b];
            y[e.b] -= e.H*p[e.a];
        }
        sumToOwners(y);
    };
    sumToOwners(I.hDiag);
    sumToOwners(I.hR);
    for (int a = 0; a < n; ++a)
        if (!mine[a]) I.hDiag[a] = 1;  // not a row here

    // Jacobi-preconditioned conjugate gradients for the increment (Heat.cpp)
    // on the owned rows
    I.heatSolve(rep, applyA, dot, mine);

    // flux-form update with T* = T^n + dT (Heat.cpp), the ghosts' T* from
    // their owners; the fluxes into ghosts summed to their owners
    std::vector<double>& x = I.hX;
    copyToGhosts(x);
    double source = 0, exchange = 0, wall = 0, fixedGrain = 0;
    std::vector<double>& q = I.hR;
    for (int a = 0; a < n; ++a)
    {
        const int i = I.heatGrain[a];
        x[a] += I.T[i];
        q[a] = 0;
        if (!mine[a]) continue;
        const double e = I.heatH[i]*(I.heatTf[i] - x[a]);
        q[a] = I.heatQ[i] + e;
        source += dt*q[a];
        exchange += dt*e;
    }
    for (const HeatEdge& e : I.heatEdges)
    {
        const double F = e.H*(x[e.b] - x[e.a]);
        q[e.a] += F;
        q[e.b] -= F;
    }
    for (const HeatBoundary& bd : I.heatBounds)
    {
        const double F = bd.H*(bd.T - x[bd.a]);
        q[bd.a] += F;
        (bd.wall ? wall : fixedGrain) += dt*F;
    }
    sumToOwners(q);
    for (int a = 0; a < n; ++a)
        if (mine[a]) I.T[I.heatGrain[a]] += dt*q[a]/I.hCap[a];
    C.copyOwnersToGhosts(I.T);
    rep.sourceHeat += C.sumOverSubdomains(source);
    rep.exchangeHeat += C.sumOverSubdomains(exchange);
    rep.wallHeat += C.sumOverSubdomains(wall);
    rep.fixedGrainHeat += C.sumOverSubdomains(fixedGrain);
}

} // namespace nscd
