// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam

Application
    vansFoam

Description
    Volume-Averaged Navier-Stokes (VANS) solver for an incompressible fluid
    coupled both ways with Non-Smooth Contact Dynamics grains (thesis
    chapter 3).  The grains are mapped onto the mesh with exact grain/cell
    overlap volumes, so one scheme covers grains smaller than, equal to or
    larger than the cells.

    Step sequence (thesis Figure 3.8), one include file of this folder per
    stage: 1-2 grainMapping.H, 3 fluidStep.H, 4-5 grainStep.H, then the log
    and the finiteness checks, stepReport.H:
      1. void fraction from the grains' positions (exact overlaps, eq. 3.43)
      2. semi-implicit drag prediction (eq. 3.46-3.50)
      3. fluid: PIMPLE on the VANS momentum and the mixture volume
         conservation div(eps U) + div(phi v*) = 0 (eq. 3.51)
         [3b. heat on: fluid energy, TEqn.H (eq. 4.4-4.5, 4.13), and the
          exchanged heat handed to the grains as heat sources]
         [3c. vapour on: passive scalar psi, psiEqn.H (eq. 4.19)]
      4. fluid forces onto the grains (drag + pressure gradient, model A/B)
         [4b. coupling sources (grainCouplingSource, e.g. the droplet of
          src/dropletCoupling): advanced, their grain forces added]
      5. NSCD step of the grains (nscd::System::advance: per-pair contact
         detection, sub-stepped only on large force-driven velocity changes)

    2D: one-cell-thick mesh with empty front/back (discs); 3D: spheres.
    Settings: constant/couplingProperties, constant/grainProperties,
    constant/transportProperties (rho, nu), constant/g.

Usage
    vansFoam [-parallel]
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "couplingStepTools.H"
#include "grainRunControl.H"
#include "writeGridTime.H"
#include "fvCFD.H"
#include "pimpleControl.H"
#include "fixedFluxPressureFvPatchScalarField.H"
#include "faceReconstruct.H"
#include "fvOptions.H"

#include <sstream>

int main(int argc, char *argv[])
{
    argList::addNote
    (
        "Volume-Averaged Navier-Stokes fluid coupled with NSCD grains"
        " through exact overlap volumes"
    );

    #include "postProcess.H"
    #include "addCheckCaseOptions.H"
    #include "setRootCaseLists.H"
    grainRunControl::checkControlDict(args, {"grainState.h5", "U", "p"});
    #include "createWriteGridTime.H"
    #include "createMesh.H"
    #include "createControl.H"
    #include "createTimeControls.H"
    #include "createFields.H"
    #include "createVelocityCorrection.H"
    #include "createFvOptions.H"
    // fvOptions that exchange with the grains (grainCouplingSource, e.g.
    // vapourDropletSource) are coupled to the cloud through typed hooks
    cloud.addCouplingSources(fvOptions);
    #include "createHeatBudget.H"
    #include "createStepFiles.H"
    #include "initContinuityErrs.H"
    grainRunControl runControl(runTime);
    // the start time's lagrangian output located on this mesh (the state
    // may have been written on another mesh, e.g. a deposit copied in)
    cloud.grains().writeCloud();

    #include "createCouplingStepTimer.H"

    Info<< "\nStarting time loop\n" << endl;

    while (runTime.run())
    {
        #include "readTimeControls.H"
        #include "CourantNo.H"
        #include "setDeltaT.H"

        // a collapsing time step means the coupling went unstable: stop
        // with the last written time as the last good state
        checkTimeStepCollapse
        (
            runTime, adjustTimeStep, maxDeltaT,
            "reduce maxDeltaT/maxCo in system/controlDict, or use the overlap"
            " void fraction (the particle-centroid method is unstable for"
            " dense packings, thesis 3.2.2)."
        );
        #include "advanceCouplingTime.H"

        // 1. void fraction, 2. drag prediction (t0, t1)
        #include "grainMapping.H"
        // 3. fluid: PIMPLE (U, p), [3b. T], [3c. psi] (t2)
        #include "fluidStep.H"
        // 4. fluid forces on the grains, [4b. coupling sources], 5. NSCD
        #include "grainStep.H"
        #include "stepReport.H"

        if (!runControl.writeStep([&]() { cloud.write(); }))
        {
            break;
        }

        timingFile.write
        (
            &cloud.grains(),
            scalarList({timer.mapping, timer.fluid, timer.contacts})
        );
        runTime.printExecutionTime(Info);
    }

    timer.report();

    Info<< "End\n" << endl;
    return 0;
}
