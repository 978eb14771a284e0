// SPDX-License-Identifier: GPL-3.0-or-later
#include "resolvedGrains.H"
#include "syncTools.H"
#include "fvc.H"
#include "fvMatrices.H"
#include "zeroGradientFvPatchFields.H"
#include "PstreamReduceOps.H"

// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::resolvedGrains::resolvedGrains
(
    const fvMesh& mesh,
    const grainCloud& grains,
    const overlapMeshAdapter& adapter,
    const vansCloudSettings& settings,
    const fluidProperties& fluid,
    const wordList& patchTypes
)
:
    mesh_(mesh),
    grains_(grains),
    adapter_(adapter),
    settings_(settings),
    fluid_(fluid),
    Bs_
    (
        IOobject("Bs", mesh.time().timeName(), mesh),
        mesh, dimensionedScalar(dimless, Zero), patchTypes
    ),
    // Kg: gamma* dt/rho [-] (kinematic) or gamma* dt [kg/m^3] (dynamic)
    Kg_
    (
        IOobject("Kg", mesh.time().timeName(), mesh),
        mesh,
        dimensionedScalar(fluid.kinematic() ? dimless : dimDensity, Zero),
        patchTypes
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
    fixedResolved_ = false;
    // off: every grain unresolved (the same decision on every rank;
    // decomposed: a rank without grains goes on, the sums below are
    // collective)
    if (!(settings_.resolvedCellsPerDiameter < GREAT))
    {
        return;
    }
    const scalar depth = adapter_.depth();
    const bool twoD = adapter_.twoD();
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    // per grain: the sum of its cells' sizes and their number (its cells
    // may be on several ranks: summed over the copies or the ranks)
    std::vector<double> sums(2*n, 0.0);
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const scalar Vc = mesh_.V()[ec[e]];
        sums[2*eg[e]] += twoD ? std::sqrt(Vc/depth) : std::cbrt(Vc);
        sums[2*eg[e] + 1] += 1;
    }
    if (Pstream::parRun())
    {
        adapter_.sumOverRanks(sums, 2);
    }
    for (label i = 0; i < n; ++i)
    {
        if (sums[2*i + 1] > 0)
        {
            const scalar h = sums[2*i]/sums[2*i + 1];
            resolved_[i] =
                2*s.radii()[i] >= settings_.resolvedCellsPerDiameter*h;
        }
    }
    fixedResolved_ = false;
    forAll(resolved_, i)
    {
        fixedResolved_ = fixedResolved_ || (resolved_[i] && s.fixed(i));
    }
    // (decomposed: the same pressure scheme on every rank)
    reduce(fixedResolved_, orOp<bool>());
}


Foam::tmp<Foam::volScalarField> Foam::resolvedGrains::simplecRAU
(
    const fvMatrix<vector>& UEqn,
    const volScalarField& rAU
) const
{
    // SIMPLEC-consistent pressure coefficient rAtU = 1/(A - H1).
    // Resolved free grains with the viscosity penalty: its large
    // off-diagonal coefficients make 1/A inside the grain ~h^2/(lambda nu)
    // instead of ~dt rho/rho_p, so that the pressure could no longer move
    // the grain and PISO diverges (measured).  rAtU keeps the grain's
    // inertia; the difference rAU - rAtU acts on the pressure of the
    // previous corrector (deferred, exact at convergence, as pimpleFoam's
    // `consistent`).
    // Resolved FIXED grains: the same scheme.  With 1/A the pressure
    // inside the fixed penalised grain is undetermined (eps rAU ~ eps/K ->
    // 0, no solid flux term): |p| ~ 1.4e5 Pa inside against ~10 outside,
    // and its gradient in the rim cells drove a tangential jet around a
    // spinning fixed disc (2.0 x Couette at r = 1.06 R,
    // tests/cases/test_rotationCoupling.py).  With rAtU the fluid's
    // pressure coefficient is ~dt instead of ~h^2/(4 nu), so are the rim
    // faces' (linear mean), and the field converges to the Couette profile
    // (docs/validation/resolvedGrains.md).  Same fixed point as with 1/A
    // (the deferred part vanishes when p = p_old); only the PISO iteration
    // differs.
    tmp<volScalarField> trAtU(1.0/(1.0/rAU - UEqn.H1()));
    if (fluid_.kinematic())
    {
        return trAtU;
    }
    // Dynamic form (vansInterFoam, p_rgh): rAtU only in the cells that a
    // resolved grain overlaps, rAU elsewhere.  With rAtU everywhere the
    // free surface, where -Dp snGrad(p_rgh) balances -Dp gh_f snGrad(rho)
    // (the rho part is known, with rAU in phig), was balanced only at
    // PISO convergence: a resolved disc resting on the floor 8 D below the
    // surface left 0.05-0.09 m/s in the surface's water cells and up to
    // 1.6 m/s in the air over 0.05 s (1e-3 m/s with the option off;
    // measured, tests/cases/test_resolvedInterFoam.py).
    volScalarField& rAtU = trAtU.ref();
    scalarField inside(mesh_.nCells(), 0.0);
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        if (resolved_.size() > eg[e] && resolved_[eg[e]])
        {
            inside[ec[e]] = 1;
        }
    }
    // and one layer of cells around them (the rim faces see rAtU on both
    // sides: with the bare overlap the added mass of a released disc fell
    // to 0.83 of C_A = 1, measured), across processor faces too (the
    // neighbour rank's cells, syncTools), so that a decomposed run marks
    // the serial run's cells
    {
        const scalarField core(inside);
        const labelUList& own = mesh_.owner();
        const labelUList& nei = mesh_.neighbour();
        forAll(nei, facei)
        {
            if (core[own[facei]] > 0 || core[nei[facei]] > 0)
            {
                inside[own[facei]] = 1;
                inside[nei[facei]] = 1;
            }
        }
        scalarField nbrCore;
        syncTools::swapBoundaryCellList(mesh_, core, nbrCore);
        const label start = mesh_.nInternalFaces();
        forAll(nbrCore, bFacei)
        {
            if (nbrCore[bFacei] > 0)
            {
                inside[own[start + bFacei]] = 1;
            }
        }
    }
    forAll(inside, celli)
    {
        if (inside[celli] == 0)
        {
            rAtU.primitiveFieldRef()[celli] = rAU[celli];
        }
    }
    // boundary values: a non-coupled face keeps rAtU where its cell is
    // marked and takes rAU elsewhere; a coupled (processor, cyclic) face
    // takes its neighbour cell's value, by evaluation
    forAll(rAtU.boundaryField(), patchi)
    {
        fvPatchScalarField& pf = rAtU.boundaryFieldRef()[patchi];
        if (pf.coupled())
        {
            continue;
        }
        const labelUList& fc = pf.patch().faceCells();
        forAll(pf, facei)
        {
            if (inside[fc[facei]] == 0)
            {
                pf[facei] = rAU.boundaryField()[patchi][facei];
            }
        }
    }
    rAtU.correctBoundaryConditions();
    return trAtU;
}


bool Foam::resolvedGrains::finalPressureSolve() const
{
    // The deferred part of the SIMPLEC coefficient, (rAU - rAtU) grad p,
    // takes the pressure of the previous corrector.  In a run's first step
    // that is the initial field, not a converged one, and a first corrector
    // solved to relTol leaves its error in the step's result: a resolved
    // disc of rho_p/rho_f = 1.01 released in vansInterFoam (relTol 0.01, 2
    // correctors) moved up in its first step and its fitted initial
    // acceleration was 0.835 of the added-mass value; with the first step
    // solved to the final tolerance 0.958 (tests/cases/
    // test_resolvedInterFoam.py).  Later steps start from the previous
    // step's converged pressure.
    const Time& runTime = mesh_.time();
    return
        simplecPressure()
     && runTime.timeIndex() == runTime.startTimeIndex() + 1;
}


void Foam::resolvedGrains::checkUSolver(const volVectorField& U) const
{
    // the penalty makes the U matrix nearly singular inside the grain
    // (viscous coupling ~lambda nu/h^2 against ~rho_p/(rho dt)):
    // Gauss-Seidel stalls there (1000 sweeps, residual 1e-3, measured), a
    // Krylov solver converges in ~15 iterations
    if
    (
        rigidViscosity()
     && mesh_.solverDict(U.select(false))
            .getOrDefault<word>("solver", word::null) == "smoothSolver"
    )
    {
        WarningInFunction
            << "rigidViscosityRatio " << settings_.rigidViscosityRatio
            << " (resolved free grains) with the smoothSolver for U in "
            << "system/fvSolution: it stalls inside the grains."
            << nl << "    Fix: \"(U|UFinal)\" { solver PBiCGStab;"
            << " preconditioner DILU; tolerance 1e-9; relTol 0; }" << endl;
    }
}


Foam::tmp<Foam::surfaceScalarField>
Foam::resolvedGrains::rigidViscosityf() const
{
    if (!fluid_.kinematic())
    {
        FatalErrorInFunction
            << "rigidViscosityf(): constant properties only; with a"
            << " variable fluid call rigidViscosityf(mu)" << exit(FatalError);
    }
    const dimensionedScalar nu("nu", dimViscosity, fluid_.nu());
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


Foam::tmp<Foam::surfaceScalarField>
Foam::resolvedGrains::rigidViscosityf(const volScalarField& mu) const
{
    // Dynamic form (vansInterFoam: rho, mu per cell, momentum in rho U):
    // the penalised viscosity mu (1 + lambda chi) [Pa s] with the cell's
    // own mixture viscosity mu = rho nu, its harmonic face mean minus the
    // face viscosity of the solver's own term laplacian(mu, U) (its linear
    // face mean), clipped at 0.  The clip also removes the negative
    // difference (harmonic - linear mean) where mu jumps across the free
    // surface outside the grains (chi = 0 on both sides).  Same chi as
    // the constant form above: both solvers penalise the same cells.
    const volScalarField chi(max(2*Br_ - 1, dimensionedScalar(dimless, Zero)));
    const volScalarField muPen(mu*(1 + settings_.rigidViscosityRatio*chi));
    return max
    (
        1/fvc::interpolate(1/muPen) - fvc::interpolate(mu),
        dimensionedScalar(mu.dimensions(), Zero)
    );
}


// ************************************************************************* //
