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
            Info<< "heat: grain mean T = " << grains.meanTemperature()
                << " K, wall heat = " << rep.wallHeat << " J";
            if (rep.exchangeHeat != 0)
            {
                // grainProperties frontRearWalls (2D Hele-Shaw cell)
                Info<< ", front/rear walls = " << rep.exchangeHeat << " J";
            }
            for (const auto& r : grains.wallHeatRates(runTime.deltaTValue()))
            {
                Info<< ", " << r.first << " " << r.second << " W";
            }
            Info<< ", CG iterations " << rep.heatIterations << endl;
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

        runTime.printExecutionTime(Info);
    }

    Info<< "End\n" << endl;
    return 0;
}
