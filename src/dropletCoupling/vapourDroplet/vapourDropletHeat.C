// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet heat and vapour (see vapourDroplet.H)

Description
    Heat and mass (eq. 4.16: L mdot = Q_f + Q_p + Q_film), the vapour volume
    source q_c [1/s] of the ring of cells outside the droplet (uniform or
    heatFlux release) or of the cells of the grains that heat it (grains
    release), the heat sink directions of vapourRelease heatFlux, each
    grain's heat of vapourRelease grains, and the Leidenfrost film
    conduction of the grains pressed on the surface.
\*---------------------------------------------------------------------------*/

#include "vapourDroplet.H"
#include "vansCloud.H"
#include "grainSums.H"
#include "mathematicalConstants.H"

#include <cmath>

using Foam::constant::mathematical::pi;

// * * * * * * * * * * * * * * * * Local helpers * * * * * * * * * * * * * * //

namespace
{

//- fn(grain i, local cell c, V_ic/W_i) for every local overlap of the
//  grains' mapping ga with a mapped volume W_i > 0 (summed over the ranks)
template<class Fn>
void forEachGrainCell(const Foam::overlapMeshAdapter& ga, const Fn& fn)
{
    const std::vector<double>& W = ga.grainMappedVolume();
    const auto& eg = ga.entryGrain();
    const auto& ec = ga.entryCell();
    const auto& ev = ga.entryVolume();
    for (std::size_t e = 0; e < eg.size(); ++e)
    {
        if (W[eg[e]] > 0)
        {
            fn(Foam::label(eg[e]), Foam::label(ec[e]), ev[e]/W[eg[e]]);
        }
    }
}

} // End anonymous namespace

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vapourDroplet::releaseWeights(const scalar h)
{
    releaseWeight_ = 0;
    if (!localRelease_ || !blowing_ || sinkHeat_.empty())
    {
        return;
    }
    const scalarField& V = mesh_.V();
    const scalar R = radius();
    const scalar alpha = min(0.5*pi, max(pi/16, 2*h/max(R, VSMALL)));
    const scalar cosAlpha = std::cos(alpha);

    // local ring cells and their directions from the centre
    DynamicList<label> cells;
    DynamicList<vector> dirs;
    forAll(ring_, ci)
    {
        if (ring_[ci] > 0)
        {
            cells.append(ci);
            dirs.append(directionTo(mesh_.C()[ci]));
        }
    }
    const label ns = sinkHeat_.size();
    auto inCone = [&](const label s, const label j)
    {
        const vector& n = sinkDirection_[s];
        return magSqr(n) == 0 || (n & dirs[j]) >= cosAlpha;
    };

    // A_c: ring volume in each sink cell's cone, over all ranks
    scalarList A(ns, Zero);
    for (label s = 0; s < ns; ++s)
    {
        forAll(cells, j)
        {
            if (inCone(s, j))
            {
                A[s] += ring_[cells[j]]*V[cells[j]];
            }
        }
    }
    Pstream::listCombineGather(A, plusEqOp<scalar>());
    Pstream::listCombineScatter(A);
    const scalar Wring = gSum(ring_*V);
    if (!(Wring > 0))
    {
        return;
    }

    for (label s = 0; s < ns; ++s)
    {
        const scalar heat = sinkHeat_[s];
        forAll(cells, j)
        {
            const label ci = cells[j];
            if (A[s] > 0)
            {
                if (inCone(s, j))
                {
                    releaseWeight_[ci] += heat*ring_[ci]*V[ci]/A[s];
                }
            }
            else
            {
                releaseWeight_[ci] += heat*ring_[ci]*V[ci]/Wring;
            }
        }
    }
}


void Foam::vapourDroplet::grainReleaseWeights()
{
    releaseWeight_ = 0;
    if (!blowing_)
    {
        return;
    }
    // the gas's share (Q_f of the last step) over the ring, as uniform
    const scalarField& V = mesh_.V();
    const scalar Wring = gSum(ring_*V);
    if (Wring > 0)
    {
        releaseWeight_ = max(Qf_, scalar(0))*ring_*V/Wring;
    }
    if (!cloud_)
    {
        return;
    }
    // each grain's share over its cells by the exact overlaps V_ic/W_i
    // (local entries; W_i summed over the ranks), and in the same pass the
    // overlap-weighted size of its cells (sqrt(V/depth) in 2D, cbrt(V) in
    // 3D) for checkReleasingGrainSizes
    const UList<scalar> Q
    (
        cloud_->grains().column<scalar>(grainVapourColumn)
    );
    const scalar depth = adapter_.depth();
    const bool twoD = adapter_.twoD();
    scalarList h(Q.size(), Zero);
    forEachGrainCell
    (
        cloud_->adapter(),
        [&](const label gi, const label c, const scalar f)
        {
            if (gi < Q.size() && Q[gi] > 0)
            {
                releaseWeight_[c] += Q[gi]*f;
                h[gi] += f*(twoD ? std::sqrt(V[c]/depth) : std::cbrt(V[c]));
            }
        }
    );
    checkReleasingGrainSizes(h);
}


void Foam::vapourDroplet::checkReleasingGrainSizes(List<scalar>& h) const
{
    grainTools::sumOverCopies(cloud_->grains(), h);
    const nscd::System& sys = cloud_->grains().system();
    const auto& r = sys.radii();
    forAll(h, gi)
    {
        if (h[gi] > 0 && 2*r[gi] > 2*h[gi])
        {
            FatalIOErrorInFunction(dict_)
                << "vapourRelease grains in " << dict_.name() << ": grain "
                << sys.grainIds()[gi] << " (diameter " << 2*r[gi]
                << " m) heats the droplet"
                << " but is " << 2*r[gi]/h[gi] << " times the size of the"
                << " cells it overlaps (" << h[gi] << " m): the cells it"
                << " covers have no gas for its vapour." << nl
                << "    Fix: vapourRelease uniform or heatFlux for grains"
                << " larger than about two cells, or a mesh whose cells are"
                << " at least half the grain diameter." << exit(FatalIOError);
        }
    }
}


void Foam::vapourDroplet::computeFilmHeat
(
    const nscd::System& sys,
    const scalar dt
)
{
    filmGrain_.clear();
    filmHeat_.clear();
    if (!film_ || barrierId_ < 0 || !(m_ > 0))
    {
        return;
    }
    // decomposed grains: the grain's normal impulse on the droplet is its
    // owner's (zero in a ghost, nscd::Subdomain); the heat is computed
    // there and copied to the ghosts (so that every copy gives it)
    const bool decomposed = cloud_->grains().decomposed();
    List<scalar> perGrain(decomposed ? label(sys.size()) : 0, Zero);
    const scalar depth = adapter_.depth();
    const std::vector<double>& rn = sys.droplet(barrierId_).grainImpulse;
    const std::vector<double>& T = sys.temperatures();
    DynamicList<label> grains;
    DynamicList<scalar> heat;
    for (std::size_t i = 0; i < rn.size(); ++i)
    {
        const scalar F = rn[i]/dt;      // N/m (2D, nscd units)
        const scalar dT = T[i] - Td_;
        if (!(F > 0) || !(dT > 0))
        {
            continue;
        }
        const scalar c = sys.material(sys.materials()[i]).heatCapacity;
        const bool bath = sys.fixedTemperature(i);
        if (!(c > 0) && !bath)
        {
            continue;   // temperature not integrated: no heat to give
        }
        const scalar r = sys.radii()[i];
        const scalar delta = filmThickness(r, F, dT, muV_, kappaF_, rhoV_, L_);
        const scalar G = pi*kappaF_*std::sqrt(2*r/delta);     // W/(m K)
        const scalar C = sys.mass(i)*c;                        // J/(m K)
        const scalar Gstar = bath ? G : G*C/(C + dt*G);
        if (decomposed)
        {
            perGrain[i] = Gstar*dT*depth;
            continue;
        }
        grains.append(label(i));
        heat.append(Gstar*dT*depth);                           // W
    }
    if (decomposed)
    {
        grainTools::sumOverCopies(cloud_->grains(), perGrain);
        forAll(perGrain, i)
        {
            if (perGrain[i] > 0)
            {
                grains.append(i);
                heat.append(perGrain[i]);
            }
        }
    }
    filmGrain_.transfer(grains);
    filmHeat_.transfer(heat);
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vapourDroplet::setHeatSink(const scalarField& sink)
{
    if (!localRelease_)
    {
        return;
    }
    DynamicList<vector> dirs;
    DynamicList<scalar> heat;
    forAll(sink, ci)
    {
        // cells that gave heat to the droplet (a cell slightly below T_d,
        // s_c < 0, releases nothing: the release weights stay >= 0)
        if (sink[ci] > 0)
        {
            dirs.append(directionTo(mesh_.C()[ci]));
            heat.append(sink[ci]*mesh_.V()[ci]);
        }
    }
    // the film heat enters at the grains: decomposed, each owner adds its
    // grains before the gather; replicated, after it (the same list on
    // every rank)
    const bool decomposed = cloud_ && cloud_->grains().decomposed();
    if (decomposed)
    {
        addFilmSinks(dirs, heat, true);
    }
    List<List<vector>> allDirs(Pstream::nProcs());
    List<List<scalar>> allHeat(Pstream::nProcs());
    allDirs[Pstream::myProcNo()] = dirs;
    allHeat[Pstream::myProcNo()] = heat;
    Pstream::gatherList(allDirs);
    Pstream::scatterList(allDirs);
    Pstream::gatherList(allHeat);
    Pstream::scatterList(allHeat);
    sinkDirection_ =
        ListListOps::combine<List<vector>>(allDirs, accessOp<List<vector>>());
    sinkHeat_ =
        ListListOps::combine<List<scalar>>(allHeat, accessOp<List<scalar>>());

    if (!decomposed)
    {
        DynamicList<vector> filmDirs;
        DynamicList<scalar> filmHeat;
        addFilmSinks(filmDirs, filmHeat, false);
        sinkDirection_.append(filmDirs);
        sinkHeat_.append(filmHeat);
    }
}


void Foam::vapourDroplet::addFilmSinks
(
    DynamicList<vector>& dirs,
    DynamicList<scalar>& heat,
    const bool ownedOnly
) const
{
    if (!film_ || filmGrain_.empty() || !cloud_)
    {
        return;
    }
    const grainCloud& grains = cloud_->grains();
    const nscd::System& sys = grains.system();
    forAll(filmGrain_, k)
    {
        const label i = filmGrain_[k];
        if
        (
            i >= label(sys.size()) || !(filmHeat_[k] > 0)
         || (ownedOnly && !grains.owned(i))
        )
        {
            continue;
        }
        const auto& xg = sys.positions()[i];
        dirs.append(directionTo(vector(xg[0], xg[1], xg[2])));
        heat.append(filmHeat_[k]);
    }
}


Foam::scalar Foam::vapourDroplet::filmThickness
(
    const scalar r,
    const scalar F,
    const scalar dT,
    const scalar muV,
    const scalar k,
    const scalar rhoV,
    const scalar L
)
{
    // I = int_0^inf s atan(s)/(1 + s^2)^3 ds (vapourDroplet.H)
    constexpr scalar I = 0.147262;
    return std::pow
    (
        24*I*muV*k*dT*std::pow(2*r, 1.5)/(rhoV*L*F),
        0.4
    );
}


Foam::scalar Foam::vapourDroplet::setLiquidHeat()
{
    liquidHeat_.clear();
    if (!(kL_ > 0) || !cloud_ || !(m_ > 0))
    {
        return 0;
    }
    const grainHeatExchange& heat = cloud_->heat();
    const List<scalar>& Hs = heat.conductance();
    const List<scalar>& T0 = heat.startTemperature();
    const nscd::System& sys = cloud_->grains().system();
    const label n = sys.size();
    // (the same answer on every rank: the sums below are collective)
    bool ready = Hs.size() == n && T0.size() == n;
    if (cloud_->grains().decomposed())
    {
        reduce(ready, andOp<bool>());
    }
    if (!ready)
    {
        return 0;
    }
    // x_i = sum_c chi_c V_ic/W_i, the part of grain i inside the droplet
    List<scalar> x(n, Zero);
    forEachGrainCell
    (
        cloud_->adapter(),
        [&](const label gi, const label c, const scalar f)
        {
            if (gi < n && chi_[c] > 0)
            {
                x[gi] += chi_[c]*f;
            }
        }
    );
    grainTools::sumOverCopies(cloud_->grains(), x);
    // the liquid's conductance of the part inside, H x (k_l/kappa), of
    // which vansCloud's exchange already gives H x: the extra
    // G = H x (k_l/kappa - 1), implicit with the grain's capacity C as
    // H* (grainHeatExchange.H), E = (H + G) C/(C + dt (H + G)) - H*
    const scalar dt = mesh_.time().deltaTValue();
    const scalar depth = adapter_.depth();
    const scalar f = kL_/kappaF_ - 1;
    liquidHeat_.setSize(n, Zero);
    for (label i = 0; i < n; ++i)
    {
        const scalar dT = T0[i] - Td_;
        if (!(x[i] > 0) || !(dT > 0) || !(Hs[i] > 0))
        {
            continue;
        }
        const bool bath = sys.fixedTemperature(i);
        const scalar C =
            sys.mass(i)*sys.material(sys.materials()[i]).heatCapacity*depth;
        if (!(C > 0) && !bath)
        {
            continue;   // temperature not integrated: no heat to give
        }
        const scalar H = bath ? Hs[i] : Hs[i]*C/(C - dt*Hs[i]);
        const scalar Ht = H*(1 + f*x[i]);
        const scalar E = (bath ? Ht : Ht*C/(C + dt*Ht)) - Hs[i];
        liquidHeat_[i] = max(E, scalar(0))*dT;
    }
    return grainTools::sumOverGrains(cloud_->grains(), liquidHeat_);
}


Foam::scalar Foam::vapourDroplet::setGrainHeat(const scalarField& T)
{
    if (!grainRelease_ || !cloud_)
    {
        return 0;
    }
    const grainHeatExchange& heat = cloud_->heat();
    const List<scalar>& H = heat.conductance();
    const List<scalar>& T0 = heat.startTemperature();
    const label n = cloud_->grains().system().size();
    List<scalar> Q(n, Zero);
    if (H.size() == n && T0.size() == n)
    {
        // grain i's part of Q_p: its exchange with the penalised cells
        // (vansCloud's KT, KTTp term by term, grainHeatExchange.H)
        forEachGrainCell
        (
            cloud_->adapter(),
            [&](const label gi, const label c, const scalar f)
            {
                if (gi < n && chi_[c] > 0)
                {
                    Q[gi] += chi_[c]*f*H[gi]*(T0[gi] - T[c]);
                }
            }
        );
    }
    grainTools::sumOverCopies(cloud_->grains(), Q);
    const scalar Qp = grainTools::sumOverGrains(cloud_->grains(), Q);
    // the liquid heat enters at its grain
    forAll(liquidHeat_, i)
    {
        if (i < n)
        {
            Q[i] += liquidHeat_[i];
        }
    }
    // the film heat enters at the grain pressed on the surface
    if (film_)
    {
        forAll(filmGrain_, k)
        {
            if (filmGrain_[k] < n)
            {
                Q[filmGrain_[k]] += filmHeat_[k];
            }
        }
    }
    UList<scalar> column
    (
        cloud_->grains().column<scalar>(grainVapourColumn)
    );
    column.deepCopy(Q);
    return Qp;
}


Foam::tmp<Foam::scalarField>
Foam::vapourDroplet::volumeSource(const scalar Vdot) const
{
    auto tq = tmp<scalarField>::New(ring_.size(), Zero);
    if (localRelease_ || grainRelease_)
    {
        const scalar S = gSum(releaseWeight_);
        if (S > 0)
        {
            tq.ref() = Vdot*releaseWeight_/(S*mesh_.V());
            return tq;
        }
    }
    const scalar W = gSum(ring_*mesh_.V());
    if (W > 0)
    {
        tq.ref() = Vdot*ring_/W;
    }
    return tq;
}


Foam::List<Foam::scalar> Foam::vapourDroplet::heatIntoGrains() const
{
    // the film heat of the grains pressed on the surface in the last NSCD
    // step leaves them over this step (the same grains as Q_film of setHeat)
    // and the liquid heat of this step (setLiquidHeat) leaves its grain
    List<scalar> Q;
    if ((film_ || liquidHeat_.size()) && cloud_)
    {
        const label n = cloud_->grains().system().size();
        const scalar depth = adapter_.depth();
        Q.setSize(n, Zero);
        forAll(filmGrain_, k)
        {
            if (filmGrain_[k] < n)
            {
                Q[filmGrain_[k]] -= filmHeat_[k]/depth;
            }
        }
        forAll(liquidHeat_, i)
        {
            if (i < n)
            {
                Q[i] -= liquidHeat_[i]/depth;
            }
        }
    }
    return Q;
}


void Foam::vapourDroplet::setHeat(const scalar Qf, const scalar Qp)
{
    const scalar dt = mesh_.time().deltaTValue();
    Qf_ = Qf;
    Qp_ = Qp;
    // Leidenfrost film heat of the grains pressed on the surface (last NSCD
    // step), taken from them over this step by vansCloud's heat sources
    // (over every grain once: the owned ones, reduced when decomposed)
    Qfilm_ = 0;
    if (film_ && cloud_)
    {
        const grainCloud& grains = cloud_->grains();
        const label n = grains.system().size();
        forAll(filmGrain_, k)
        {
            if (filmGrain_[k] < n && grains.owned(filmGrain_[k]))
            {
                Qfilm_ += filmHeat_[k];
            }
        }
        if (grains.decomposed())
        {
            reduce(Qfilm_, sumOp<scalar>());
        }
    }
    // the grains' extra heat to the liquid of this step (setLiquidHeat)
    if (cloud_)
    {
        Qfilm_ += grainTools::sumOverGrains(cloud_->grains(), liquidHeat_);
    }
    mdot_ = (Qf_ + Qp_ + Qfilm_)/L_;     // eq. 4.16
    scalar loss = mdot_*dt;
    if (loss > m_)
    {
        loss = m_;
    }
    m_ -= loss;
    pendingVapour_ += loss;
}

// ************************************************************************* //
