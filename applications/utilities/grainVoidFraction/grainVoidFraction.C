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

    Parallel (-parallel): the grains are read whole from the undecomposed
    <case>/<time>/grainState.h5 on every rank; each rank writes the fields
    of its sub-mesh (reconstructPar to collect them).  Grains straddling a
    processor boundary are split exactly between the ranks.

Usage
    grainVoidFraction [-time ranges | -latestTime | -noZero ...] [-parallel]
\*---------------------------------------------------------------------------*/

#include "overlapMeshAdapter.H"
#include "grainCloud.H"
#include "fvCFD.H"
#include "timeSelector.H"
#include "zeroGradientFvPatchFields.H"

using namespace Foam;

// Self-check of spread/gather (same result serial and parallel):
//  - sum_c f_c V_c == sum_g F_g  (Newton's third law, eq. 3.42)
//  - gather of a uniform field returns it (partition of unity)
//  - sum_g a_g . F_g == sum_c a_c . f_c V_c  (adjointness)
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

int main(int argc, char *argv[])
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
    timeSelector::addOptions();   // 0/ included (grainDeposit writes it)

    #include "setRootCase.H"
    #include "createTime.H"

    instantList timeDirs = timeSelector::select0(runTime, args);

    #include "createMesh.H"

    dictionary settings;
    {
        IOobject io
        (
            "overlapMappingDict",
            runTime.system(),
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
    }

    overlapMeshAdapter adapter(mesh, settings);
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

        if (args.found("checkCoupling"))
        {
            checkCoupling(adapter);
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
