/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud, resolved grains and the fluid's view of a grain's mass

Description
    Which grains get the resolved scheme (markResolved, fixedResolved), the
    viscosity penalty of their rigid interior (rigidViscosityf), and the
    inverse mass the fluid's prediction uses (held fraction, eq. 3.46-3.50).
    See vansCloud.H, "Resolved grains", and docs/validation/resolvedGrains.md.
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "fvc.H"
#include "PstreamCombineReduceOps.H"

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vansCloud::markResolved()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    resolved_.setSize(n);
    resolved_ = false;
    // without constant properties (vansInterFoam) the solver does not add
    // the B part of the solid flux: keep every grain unresolved
    if (!settings_.constantProperties || n == 0)
    {
        return;
    }
    const scalar depth = adapter_.depth();
    const bool twoD = adapter_.twoD();
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    List<scalar> hSum(n, Zero);
    List<scalar> nSum(n, Zero);
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const scalar Vc = mesh_.V()[ec[e]];
        hSum[eg[e]] += twoD ? std::sqrt(Vc/depth) : std::cbrt(Vc);
        nSum[eg[e]] += 1;
    }
    if (Pstream::parRun())
    {
        Pstream::listCombineGather(hSum, plusEqOp<scalar>());
        Pstream::listCombineScatter(hSum);
        Pstream::listCombineGather(nSum, plusEqOp<scalar>());
        Pstream::listCombineScatter(nSum);
    }
    for (label i = 0; i < n; ++i)
    {
        if (nSum[i] > 0)
        {
            const scalar h = hSum[i]/nSum[i];
            resolved_[i] = 2*s.radii()[i] >= settings_.resolvedCellsPerDiameter*h;
        }
    }
}


void Foam::vansCloud::initHeldFraction()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    if (heldFraction_.size() == n)
    {
        return;
    }
    heldFraction_.setSize(n);
    heldFraction_ = 0;
    for (const nscd::System::ContactView& c : s.contacts())
    {
        if (c.impulse.squaredNorm() > 0)
        {
            heldFraction_[c.i] = 1;
            if (c.j >= 0)
            {
                heldFraction_[c.j] = 1;
            }
        }
    }
}


Foam::scalar Foam::vansCloud::fluidInverseMass(const label i) const
{
    // a held grain is seen 1e4 times heavier, not infinitely: where eps is
    // clipped at epsMin the drag coefficient is astronomical and gamma*
    // must stay bounded (<= 1e4 m/(W dt)) for a well-posed pressure equation
    const scalar theta = resolved_[i] ? 0 : heldFraction_[i];
    return (1 - theta*(1 - 1e-4))/grains_.system().mass(i);
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

bool Foam::vansCloud::fixedResolved() const
{
    const nscd::System& s = grains_.system();
    if (resolved_.size() != label(s.size()))
    {
        return false;
    }
    forAll(resolved_, i)
    {
        if (resolved_[i] && s.fixed(i))
        {
            return true;
        }
    }
    return false;
}


Foam::tmp<Foam::surfaceScalarField> Foam::vansCloud::rigidViscosityf() const
{
    const dimensionedScalar nu("nu", dimViscosity, settings_.nu);
    // chi = max(0, 2 Br - 1): 0 in cells at most half covered, 1 in fully
    // covered ones, continuous in Br (smooth in time as the grain moves)
    const volScalarField chi(max(2*Br_ - 1, dimensionedScalar(dimless, Zero)));
    const volScalarField nuPen(nu*(1 + settings_.rigidViscosityRatio*chi));
    // harmonic face mean (viscosities in series), minus the fluid's own nu,
    // clipped at 0 (round-off where neither cell is penalised)
    return max
    (
        1/fvc::interpolate(1/nuPen) - nu,
        dimensionedScalar(dimViscosity, Zero)
    );
}


// ************************************************************************* //
