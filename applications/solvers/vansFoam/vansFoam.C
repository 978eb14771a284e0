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

    Step sequence (thesis Figure 3.8):
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
#include "fvCFD.H"
#include "pimpleControl.H"
#include "fixedFluxPressureFvPatchScalarField.H"
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
    #include "createTime.H"
    #include "createMesh.H"
    #include "createControl.H"
    #include "createTimeControls.H"
    #include "createFields.H"
    #include "createFvOptions.H"
    // fvOptions that exchange with the grains (grainCouplingSource, e.g.
    // vapourDropletSource) are coupled to the cloud through typed hooks
    cloud.addCouplingSources(fvOptions);
    #include "createHeatBudget.H"
    #include "initContinuityErrs.H"
    grainRunControl runControl(runTime);
    // the start time's lagrangian output located on this mesh (the state
    // may have been written on another mesh, e.g. a deposit copied in)
    cloud.grains().writeCloud();

    // wall-clock split of the step (reported at the end)
    couplingStepTimer timer;
    using clock = couplingStepTimer::clock;
    const auto seconds = &couplingStepTimer::seconds;

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

        // an absurd velocity (a diverged previous step, a bad initial
        // field) stops here with the cause, not in the linear solver
        grainCloud::checkFluidBlowUp(U, runTime.deltaTValue(), "fluid solve");

        ++runTime;
        Info<< "Time = " << runTime.timeName() << nl << endl;

        // 1. void fraction at the grains' current positions
        const clock::time_point t0 = clock::now();
        cloud.mapGrains();
        if (cloud.modelA())
        {
            pressureFactor = eps;
        }

        // 2. semi-implicit drag prediction
        cloud.predictDrag(U, p, runTime.deltaTValue());

        const clock::time_point t1 = clock::now();

        // 3. fluid
        while (pimple.loop())
        {
            #include "UEqn.H"
            while (pimple.correct())
            {
                #include "pEqn.H"
            }
        }

        // 3b. fluid energy (heat transfer on only, thesis eq. 4.4-4.13)
        if (cloud.heatOn())
        {
            #include "TEqn.H"
        }

        // 3c. vapour fraction (transportProperties vapour {}, thesis eq.
        //     4.19); it switches cohesion off where psi >= psi^0 (eq. 4.18)
        if (psiPtr.valid())
        {
            #include "psiEqn.H"
        }

        const clock::time_point t2 = clock::now();

        // 4. fluid forces on the grains, 5. NSCD (a blown-up fluid stops
        //    here, before a grain step of ~forever)
        grainCloud::checkFluidBlowUp(U, runTime.deltaTValue(), "grain step");
        cloud.setFluidForces(U, p);
        // 4b. coupling sources (e.g. the droplet, thesis eq. 4.17): their
        //     step over this time step and their forces on the grains for
        //     the same NSCD step; afterGrainStep is called by evolve
        cloud.advanceCouplingSources(runTime.deltaTValue());
        const clock::time_point t3 = clock::now();
        cloud.evolve(runTime.deltaTValue());
        const clock::time_point t4 = clock::now();
        timer.mapping += seconds(t0, t1) + seconds(t2, t3);
        timer.fluid += seconds(t1, t2);
        timer.contacts += seconds(t3, t4);
        ++timer.steps;

        Info<< "voidFraction min/max = " << gMin(eps.primitiveField())
            << " " << gMax(eps.primitiveField())
            << ", mean grain Reynolds number = " << cloud.meanGrainReynolds()
            << ", max grain Reynolds number = " << cloud.maxGrainReynolds()
            << endl;

        if (cloud.heatOn())
        {
            const volScalarField& T = TPtr();
            const scalarField epsV(eps.primitiveField()*mesh.V());
            const scalar sumEpsV = gSum(epsV);
            const scalar Ef =
                cloud.rho()*cloud.Cp()*gSum(epsV*T.primitiveField());
            const scalar Eg = cloud.grainHeatContent();
            std::ostringstream os;
            os.precision(16);
            os  << "heat: grain mean T = " << cloud.grainMeanTemperature()
                << ", fluid mean T = " << Ef/(cloud.rho()*cloud.Cp()*sumEpsV)
                << ", exchanged Q = " << cloud.stepHeat()
                << " J, energy fluid + grains = " << Ef + Eg << " J";
            Info<< os.str().c_str() << endl;
            #include "heatBudget.H"
            if (!std::isfinite(Ef + Eg))
            {
                FatalErrorInFunction
                    << "Non-finite temperature at time " << runTime.timeName()
                    << ". The last written time holds the last good state."
                    << exit(FatalError);
            }
        }

        // no NaN/Inf: stop before writing a bad state
        if
        (
            !std::isfinite(gSum(mag(U.primitiveField())))
         || !std::isfinite(gSum(mag(p.primitiveField())))
        )
        {
            FatalErrorInFunction
                << "Non-finite fluid velocity or pressure at time "
                << runTime.timeName() << ". The last written time holds the"
                << " last good state." << nl
                << "    Fix: reduce maxCo / maxDeltaT in system/controlDict."
                << exit(FatalError);
        }

        if (!runControl.writeStep([&]() { cloud.write(); }))
        {
            break;
        }

        runTime.printExecutionTime(Info);
    }

    timer.report();

    Info<< "End\n" << endl;
    return 0;
}
