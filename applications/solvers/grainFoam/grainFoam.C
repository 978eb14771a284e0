// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam

Application
    grainFoam

Group
    grpLagrangianSolvers

Description
    Dry granular flow of rigid discs (2D) or spheres (3D) computed with
    Non-Smooth Contact Dynamics (hard contacts, Signorini + Coulomb, no
    restitution; nonlinear Gauss-Seidel with a contact queue; thesis
    chapter 2) inside an OpenFOAM case.  The walls are the mesh's wall
    patches; a one-cell-thick mesh with empty front/back selects discs.

    Settings: constant/grainProperties, gravity: constant/g.
    Initial grains: <startTime>/grainState.h5 (written by grainDeposit or by a
    previous run; startFrom latestTime continues a run bit-for-bit).
    Output at write times: <time>/lagrangian/grains (foamToVTK) and
    <time>/grainState.h5.
    Heat (thesis section 4.1.1, contact conduction): when a material has
    heatCapacity > 0 the grain temperatures are integrated (nscd), walls get
    temperatures from grainProperties wallTemperatures (others adiabatic),
    the grain temperature T is written into lagrangian/grains and every step
    logs the mean grain temperature and the wall heat.

Usage
    grainFoam [-case dir]
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "grainRunControl.H"
#include "stepTimingFile.H"
#include "writeGridTime.H"
#include "fvCFD.H"

int main(int argc, char *argv[])
{
    argList::addNote
    (
        "Dry granular flow with Non-Smooth Contact Dynamics (discs in 2D,"
        " spheres in 3D); walls are the mesh wall patches."
    );

    #include "setRootCase.H"
    grainRunControl::checkControlDict(args);
    #include "createWriteGridTime.H"
    #include "createMesh.H"
    grainRunControl runControl(runTime);

    // no reason to hold every grain: in a parallel run each rank holds the
    // grains in its cells (grainProperties grainDecomposition)
    grainCloud grains(mesh, true, "");
    grains.checkState();
    // the start time's lagrangian output located on this mesh (the state
    // may have been written on another mesh)
    grains.writeCloud();
    // a row per step in postProcessing/grainStatistics/<startTime>/
    // grainStatistics.dat and, heat on, grainHeat/<startTime>/
    // grainHeat.dat (stepDataFile; README.md "Run-time files")
    grains.writeStepStatistics();
    // computing time per step: stepTiming.dat (stepTimingFile.H)
    stepTimingFile timingFile(runTime, false);
    autoPtr<stepDataFile> heatFile;
    const bool heat = grains.heatOn();
    if (heat)
    {
        Info<< "Heat conduction on: mean grain T = "
            << grains.meanTemperature() << " K" << nl;
    }

    Info<< "\nStarting time loop\n" << endl;

    while (runTime.run())
    {
        ++runTime;
        Info<< "Time = " << runTime.timeName() << nl;

        const nscd::StepReport& rep = grains.evolve(runTime.deltaTValue());

        if (heat)
        {
            const scalar meanT = grains.meanTemperature();
            const auto rates = grains.wallHeatRates(runTime.deltaTValue());
            Info<< "heat: grain mean T = " << meanT
                << " K, wall heat = " << rep.wallHeat << " J";
            if (rep.exchangeHeat != 0)
            {
                // grainProperties frontRearWalls (2D Hele-Shaw cell)
                Info<< ", front/rear walls = " << rep.exchangeHeat << " J";
            }
            for (const auto& r : rates)
            {
                Info<< ", " << r.first << " " << r.second << " W";
            }
            Info<< ", CG iterations " << rep.heatIterations << endl;

            // the same values, a row of grainHeat.dat
            if (!heatFile.valid())
            {
                List<stepDataFile::column> columns
                ({
                    {"grainMeanT", "K", "mean grain temperature"},
                    {"wallHeat", "J", "heat from the walls into the grains"},
                    {
                        "frontRearHeat", "J",
                        "from the front and rear walls (frontRearWalls)"
                    },
                    {"CGIterations", "1", "conduction solver iterations"}
                });
                for (const auto& r : rates)
                {
                    columns.append
                    ({
                        std::string(r.first) + "_rate", "W",
                        "heat rate from wall patch " + std::string(r.first)
                    });
                }
                heatFile.reset
                (
                    new stepDataFile
                    (
                        runTime, "grainHeat",
                        "grain heat per step (the log's \"heat:\" line;"
                        " 2D: per unit depth)",
                        columns
                    )
                );
            }
            scalarList row
            ({
                meanT, rep.wallHeat, rep.exchangeHeat,
                scalar(rep.heatIterations)
            });
            for (const auto& r : rates)
            {
                row.append(r.second);
            }
            heatFile->write(row);
        }

        const bool go = runControl.writeStep
        (
            [&]()
            {
                if (heat)
                {
                    const List<scalar> T(grains.temperatures());
                    grains.write({}, {{"T", &T}});
                }
                else
                {
                    grains.write();
                }
                Info<< "Kinetic energy = " << grains.kineticEnergy() << nl;
            }
        );
        if (!go)
        {
            break;
        }

        timingFile.write(&grains, UList<scalar>());
        runTime.printExecutionTime(Info);
    }

    Info<< "End\n" << endl;
    return 0;
}
