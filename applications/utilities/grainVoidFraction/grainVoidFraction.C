// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam

Application
    grainVoidFraction

Description
    Maps the grains of every selected time holding a grainState.h5 onto the
    mesh (exact grain/cell overlaps, thesis section 3.2.1, eq. 3.43; or the
    particle-centroid method, eq. 3.44) and writes into that time directory
      - solidFraction  phi = sum_g V_gc / V_c              [-]
      - voidFraction   eps = max(1 - phi, epsMin)          [-]
    (volScalarFields, zeroGradient boundaries).  2D: discs of volume
    pi r^2 x mesh depth (see overlapMeshAdapter.H).

    Settings: optional system/overlapMappingDict (defaults otherwise)
    \verbatim
    method                  overlap;  // overlap | centroid
    epsMin                  1e-8;
    effectiveDiameterFactor 1;
    \endverbatim

    With -cellWeight it writes instead (and only) the decomposition weight
      - cellWeight  w_c = 1 + grainCost sum_g V_gc / W_g       [-]
    W_g is the grain's mapped volume, so each grain adds exactly grainCost
    over the cells it overlaps, whatever its size; grainCost (default 1000)
    is the weight of one grain in units of one fluid cell.  decomposePar
    reads it through `weightField cellWeight;` in system/decomposeParDict
    (methods scotch, ptscotch): the ranks then get equal grain counts, not
    equal cell counts (src/decompose/README.md).

    Parallel (-parallel): the grains are read whole from the undecomposed
    <case>/<time>/grainState.h5 on every rank; each rank writes the fields
    of its sub-mesh (reconstructPar to collect them).  Grains straddling a
    processor boundary are split exactly between the ranks.

Usage
    grainVoidFraction [-time ranges | -latestTime | -noZero ...] [-parallel]
        [-checkCoupling] [-cellWeight [-grainCost c]]
\*---------------------------------------------------------------------------*/

#include "overlapMeshAdapter.H"
#include "grainCloud.H"
#include "fvCFD.H"
#include "timeSelector.H"
#include "zeroGradientFvPatchFields.H"

#include <cmath>

using namespace Foam;

//- Self-check of spread/gather (same result serial and parallel):
//  - sum_c f_c V_c == sum_g F_g  (Newton's third law, eq. 3.42)
//  - gather of a uniform field returns it (partition of unity)
//  - sum_g a_g . F_g == sum_c a_c . f_c V_c  (adjointness)
//  Logs the three relative errors [-].  Error: FatalError when one is
//  above 1e-10.
static void checkCoupling(const overlapMeshAdapter& adapter)
{
    const fvMesh& mesh = adapter.mesh();
    const label n = adapter.nGrains();
    List<vector> F(n);
    forAll(F, g)
    {
        F[g] = vector(1 + 0.1*g, 2 - 0.05*g, -3 + 0.01*g*g);
    }
    volVectorField f
    (
        IOobject("grainForceDensity", mesh.time().timeName(), mesh),
        mesh,
        dimensionedVector(dimForce/dimVolume, Zero),
        zeroGradientFvPatchVectorField::typeName
    );
    adapter.spreadDensity(F, f);
    const vector total = gSum(f.primitiveField()*mesh.V().field());
    const vector expect = sum(F);
    const scalar spreadErr = mag(total - expect)/max(mag(expect), VSMALL);

    const vector u(1, 2, 3);
    volVectorField a
    (
        IOobject("a", mesh.time().timeName(), mesh),
        mesh,
        dimensionedVector("a", dimless, u)
    );
    List<vector> ag;
    adapter.gather(a, ag);
    scalar unityErr = 0;
    forAll(ag, g)
    {
        if (adapter.grainMappedVolume()[g] > 0)
        {
            unityErr = max(unityErr, mag(ag[g] - u)/mag(u));
        }
    }

    a.primitiveFieldRef() = mesh.C().primitiveField();
    adapter.gather(a, ag);
    scalar lhs = 0;
    forAll(ag, g)
    {
        lhs += ag[g] & F[g];
    }
    const scalar rhs =
        gSum((a.primitiveField() & f.primitiveField())*mesh.V().field());
    const scalar adjErr = mag(lhs - rhs)/max(mag(lhs), VSMALL);

    Info<< "    checkCoupling: spread " << spreadErr << ", unity " << unityErr
        << ", adjoint " << adjErr << endl;
    if (spreadErr > 1e-10 || unityErr > 1e-10 || adjErr > 1e-10)
    {
        FatalErrorInFunction
            << "Coupling self-check failed (relative errors above 1e-10)"
            << exit(FatalError);
    }
}

//- Decomposition weight of each local cell (see the header):
//  w_c = 1 + grainCost sum_g V_gc/W_g, dimensionless, zeroGradient; w_c >= 1
//  as scotchDecomp requires positive weights.  Sum over all cells of
//  (w_c - 1) = grainCost x number of grains mapped.
static tmp<volScalarField> cellWeight
(
    const overlapMeshAdapter& adapter,
    const scalar grainCost
)
{
    const fvMesh& mesh = adapter.mesh();
    tmp<volScalarField> tw
    (
        new volScalarField
        (
            IOobject("cellWeight", mesh.time().timeName(), mesh),
            mesh,
            dimensionedScalar("one", dimless, 1.0),
            zeroGradientFvPatchScalarField::typeName
        )
    );
    scalarField& w = tw.ref().primitiveFieldRef();
    const std::vector<double>& Wg = adapter.grainMappedVolume();
    const auto& grain = adapter.entryGrain();
    const auto& cell = adapter.entryCell();
    const auto& Vgc = adapter.entryVolume();
    for (std::size_t e = 0; e < Vgc.size(); ++e)
    {
        if (Wg[grain[e]] > 0)
        {
            w[cell[e]] += grainCost*Vgc[e]/Wg[grain[e]];
        }
    }
    tw.ref().correctBoundaryConditions();
    return tw;
}


//- Declares the application's note and options (-checkCoupling,
//  -cellWeight, -grainCost) and the time selection options.
static void addOptions()
{
    argList::addNote
    (
        "Write solidFraction and voidFraction from the grains"
        " (<time>/grainState.h5) of the selected times"
    );
    argList::addBoolOption
    (
        "checkCoupling",
        "Also check the spread (eq. 3.42) and gather of the mapping: force"
        " conservation, partition of unity and adjointness (relative errors"
        " logged; FatalError above 1e-10)"
    );
    argList::addBoolOption
    (
        "cellWeight",
        "Write only cellWeight = 1 + grainCost x (grains in the cell, split"
        " by overlap volume), the cell weights of decomposePar's"
        " `weightField cellWeight;` (scotch), instead of the fractions"
    );
    argList::addOption
    (
        "grainCost",
        "scalar",
        "With -cellWeight: weight of one grain in units of one fluid cell"
        " (default 1000: the grain counts decide the balance; the measured"
        " work ratio, ~2 for a resting bed, balances fluid + grain work)"
    );
    timeSelector::addOptions();   // 0/ included (grainDeposit writes it)
}


//- The weight of one grain in units of one fluid cell [-], option
//  -grainCost (default 1000).  Errors (FatalError): -grainCost without
//  -cellWeight, a value negative or not finite.
static scalar readGrainCost(const argList& args, const bool writeWeight)
{
    const scalar grainCost = args.lookupOrDefault<scalar>("grainCost", 1000);
    if (args.found("grainCost") && !writeWeight)
    {
        FatalErrorInFunction
            << "Option -grainCost is used only with -cellWeight: add"
            << " -cellWeight (or drop -grainCost)" << exit(FatalError);
    }
    if (!(grainCost >= 0) || !std::isfinite(grainCost))
    {
        FatalErrorInFunction
            << "Option -grainCost " << grainCost << ": the weight of one"
            << " grain in units of one fluid cell must be a finite number"
            << " >= 0"
            << exit(FatalError);
    }
    return grainCost;
}


//- The mapping settings: system/overlapMappingDict if present, else empty
//  (the defaults); logs which.
static dictionary readSettings(const fvMesh& mesh)
{
    dictionary settings;
    IOobject io
    (
        "overlapMappingDict",
        mesh.time().system(),
        mesh,
        IOobject::MUST_READ,
        IOobject::NO_WRITE
    );
    if (io.typeHeaderOk<IOdictionary>(true))
    {
        settings = IOdictionary(io);
        Info<< "Settings from " << io.objectPath() << nl;
    }
    else
    {
        Info<< "No system/overlapMappingDict: default settings" << nl;
    }
    return settings;
}


//- Logs the mapping: 2D (with its depth [m]) or 3D, method, epsMin [-] and
//  effectiveDiameterFactor [-].
static void logMapping(const overlapMeshAdapter& adapter)
{
    Info<< "Mapping: " << (adapter.twoD() ? "2D" : "3D");
    if (adapter.twoD())
    {
        Info<< ", depth " << adapter.depth() << " m";
    }
    Info<< ", method "
        << (adapter.settings().method
            == overlapMapping::MappingMethod::Exact ? "overlap" : "centroid")
        << ", epsMin " << adapter.epsMin()
        << ", effectiveDiameterFactor "
        << adapter.settings().effectiveDiameterFactor << nl << endl;
}


//- Maps the grains of statePath (the grain state of the current time) onto
//  the mesh.  Parallel: the undecomposed file is read whole on every rank.
//  Errors (FatalError): unreadable file, or (parallel) a grain system of
//  another dimension than the mesh; serial: those of grainCloud.
static void mapGrains
(
    overlapMeshAdapter& adapter,
    const fvMesh& mesh,
    const fileName& statePath
)
{
    if (Pstream::parRun())
    {
        try
        {
            const nscd::System grains(nscd::System::readHDF5(statePath));
            if (grains.dimension() != (adapter.twoD() ? 2 : 3))
            {
                FatalErrorInFunction
                    << statePath << " holds a " << grains.dimension()
                    << "D grain system but the mesh is "
                    << (adapter.twoD() ? 2 : 3) << "D" << exit(FatalError);
            }
            adapter.map(grains);
        }
        catch (const nscd::InputError& err)
        {
            FatalErrorInFunction
                << "Grain system " << statePath << ": " << err.what()
                << exit(FatalError);
        }
    }
    else
    {
        const grainCloud cloud(mesh);
        adapter.map(cloud.system());
    }
}


//- Writes cellWeight [-] of the mapped grains (cellWeight above) into the
//  current time and logs its sum and maximum.
static void writeCellWeight
(
    const overlapMeshAdapter& adapter,
    const scalar grainCost
)
{
    const fvMesh& mesh = adapter.mesh();
    tmp<volScalarField> w(cellWeight(adapter, grainCost));
    Info<< "    grains " << adapter.nGrains() << ", grainCost "
        << grainCost << ": cellWeight sum "
        << gSum(w().primitiveField()) << " over "
        << returnReduce(mesh.nCells(), sumOp<label>())
        << " cells, max " << gMax(w().primitiveField()) << endl;
    w().write();
}


//- Writes solidFraction and voidFraction [-] of the mapped grains into the
//  current time; logs the grain volume and the mapped volume [m^3] and the
//  extreme fractions.  With check, runs checkCoupling (FatalError if the
//  self-check fails).
static void writeFractions(const overlapMeshAdapter& adapter, const bool check)
{
    tmp<volScalarField> phi(adapter.solidFraction("solidFraction"));
    tmp<volScalarField> eps(adapter.voidFraction("voidFraction"));

    scalar Vs = 0;
    for (const double v : adapter.entryVolume())
    {
        Vs += v;
    }
    reduce(Vs, sumOp<scalar>());
    scalar Vg = 0;
    for (const double v : adapter.grainVolume())
    {
        Vg += v;
    }
    Info<< "    grains " << adapter.nGrains()
        << ", grain volume " << Vg << " m^3, mapped " << Vs << " m^3"
        << ", solidFraction max " << gMax(phi().primitiveField())
        << ", voidFraction min " << gMin(eps().primitiveField()) << endl;

    phi().write();
    eps().write();

    if (check)
    {
        checkCoupling(adapter);
    }
}


int main(int argc, char *argv[])
{
    addOptions();

    #include "setRootCase.H"
    #include "createTime.H"

    instantList timeDirs = timeSelector::select0(runTime, args);

    const bool writeWeight = args.found("cellWeight");
    const scalar grainCost = readGrainCost(args, writeWeight);

    #include "createMesh.H"

    const dictionary settings(readSettings(mesh));

    overlapMeshAdapter adapter(mesh, settings);
    logMapping(adapter);

    label nWritten = 0;
    forAll(timeDirs, timei)
    {
        runTime.setTime(timeDirs[timei], timei);

        // The grain state is undecomposed: in parallel read the case's file
        const fileName statePath
        (
            (Pstream::parRun() ? runTime.globalPath() : runTime.path())
           /runTime.timeName()/grainCloud::stateFileName
        );
        if (!isFile(statePath))
        {
            continue;
        }
        Info<< "Time = " << runTime.timeName() << endl;
        mesh.readUpdate();

        mapGrains(adapter, mesh, statePath);

        if (writeWeight)
        {
            writeCellWeight(adapter, grainCost);
        }
        else
        {
            writeFractions(adapter, args.found("checkCoupling"));
        }
        ++nWritten;
    }

    if (nWritten == 0)
    {
        WarningInFunction
            << "No selected time holds " << grainCloud::stateFileName
            << " (run grainDeposit first, or select other times)" << endl;
    }

    Info<< "\nEnd\n" << endl;
    return 0;
}
