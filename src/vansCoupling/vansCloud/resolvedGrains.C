// SPDX-License-Identifier: GPL-3.0-or-later
#include "resolvedGrains.H"
#include "fvc.H"
#include "zeroGradientFvPatchFields.H"
#include "PstreamCombineReduceOps.H"

// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::resolvedGrains::resolvedGrains
(
    const fvMesh& mesh,
    const grainCloud& grains,
    const overlapMeshAdapter& adapter,
    const vansCloudSettings& settings,
    const wordList& patchTypes
)
:
    mesh_(mesh),
    grains_(grains),
    adapter_(adapter),
    settings_(settings),
    Bs_
    (
        IOobject("Bs", mesh.time().timeName(), mesh),
        mesh, dimensionedScalar(dimless, Zero), patchTypes
    ),
    Kg_
    (
        IOobject("Kg", mesh.time().timeName(), mesh),
        mesh, dimensionedScalar(dimless, Zero), patchTypes
    ),
    Br_
    (
        IOobject("Br", mesh.time().timeName(), mesh),
        mesh, dimensionedScalar(dimless, Zero),
        zeroGradientFvPatchScalarField::typeName
    )
{}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::resolvedGrains::mark()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    resolved_.setSize(n);
    resolved_ = false;
    // without constant properties (vansInterFoam) the solver does not add
    // the B part of the solid flux: keep every grain unresolved
    if
    (
        !settings_.constantProperties || n == 0
     || !(settings_.resolvedCellsPerDiameter < GREAT)
    )
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


bool Foam::resolvedGrains::fixedResolved() const
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


Foam::tmp<Foam::surfaceScalarField>
Foam::resolvedGrains::rigidViscosityf() const
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


void Foam::resolvedGrains::compactRemoved()
{
    grains_.compactRemoved(resolved_);
}


// ************************************************************************* //
