/*---------------------------------------------------------------------------*\
  nscdFoam

Application
    vansInterFoam

Group
    grpMultiphaseSolvers

Description
    Two incompressible, isothermal, immiscible fluids (water/air) in the void
    space of Non-Smooth Contact Dynamics grains: interFoam's VOF method
    (MULES, CSF surface tension, p_rgh) on the Volume-Averaged
    Navier-Stokes equations of vansFoam (thesis chapter 3; the free-surface
    cases of chapter 5 use PFEM there, VOF here).

    Unknowns: U the interstitial velocity, p_rgh = p - rho g.(x - hRef),
    alpha the water volume fraction of the fluid (not of the mixture), and
    the grains.  eps is the void fraction from the exact grain/cell overlaps
    (vansCloud), phi = (eps U)_f . S_f the fluid volume flux.

        d(eps alpha)/dt + div(phiAlpha alpha) = 0            (MULES, rho = eps)
        div(phi) + div(phi_s) = 0                            (eq. 3.51)
        d(eps rho U)/dt + div(rhoPhi U) - div(mu (grad U + dev2 grad U^T))
          = -(pf + K_p) grad p + eps rho g + eps sigma kappa grad alpha
            - K (U - v**_0)  [+ phi grad(p)_grains, model B]

    with rho = alpha rho1 + (1 - alpha) rho2, mu likewise, pf = eps (model A)
    or 1 (model B), K, K v**_0, K_p, D_s the semi-implicit drag of
    eq. 3.46-3.50 computed by vansCloud in dynamic units with the mixture
    density and viscosity gathered at each grain (README.md) and
    phi_s = phi_s0 - D_s grad(p) the solid flux.  phiAlpha is phi
    corrected (Poisson, zero boundary flux) so that d(eps)/dt + div(phiAlpha)
    = 0 where grains move (alphaEqnSubCycle.H): alpha stays bounded and the
    water volume sum(eps alpha V) is conserved to round-off (closed domain,
    explicit MULES), also when the grains move.

    Step sequence: void fraction -> drag prediction -> PIMPLE (alpha
    [sub-cycled], mixture properties, U, p_rgh with the solid flux) -> fluid
    forces on the grains -> NSCD step.  Without constant/grainProperties
    there are no grains (eps = 1): the solver is then interFoam (laminar,
    static mesh, Euler).

    2D: one-cell-thick mesh with empty front/back (discs); 3D: spheres.
    Settings: constant/transportProperties (phases, sigma, phase rho/nu;
    rho, nu of the drag fluid when there are grains), constant/g, optional
    constant/grainProperties + constant/couplingProperties; alpha controls in
    system/fvSolution solvers.alpha.<phase1>.

Usage
    vansInterFoam [-parallel]
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "couplingStepTools.H"
#include "grainDictionaryTools.H"
#include "fvCFD.H"
#include "CMULES.H"
#include "EulerDdtScheme.H"
#include "gaussConvectionScheme.H"
#include "upwind.H"
#include "subCycle.H"
#include "immiscibleIncompressibleTwoPhaseMixture.H"
#include "pimpleControl.H"
#include "fvOptions.H"
#include "grainRunControl.H"

#include <sstream>

int main(int argc, char *argv[])
{
    argList::addNote
    (
        "Two immiscible incompressible fluids (VOF) in the void space of NSCD"
        " grains: Volume-Averaged Navier-Stokes, exact overlap volumes"
    );

    #include "postProcess.H"
    #include "addCheckCaseOptions.H"
    #include "setRootCaseLists.H"
    grainRunControl::checkControlDict(args, {"grainState.h5", "U", "p_rgh"});
    #include "createTime.H"
    #include "createMesh.H"
    #include "createControl.H"
    #include "createTimeControls.H"
    #include "createFields.H"
    #include "createFvOptions.H"

    #include "interstitialCourantNo.H"
    #include "setInitialDeltaT.H"
    grainRunControl runControl(runTime);
    // the start time's lagrangian output located on this mesh (the state
    // may have been written on another mesh, e.g. a deposit copied in)
    if (cloudPtr.valid())
    {
        cloudPtr->grains().writeCloud();
    }

    // wall-clock split of the step (reported at the end)
    couplingStepTimer timer;
    using clock = couplingStepTimer::clock;
    const auto seconds = &couplingStepTimer::seconds;

    Info<< "\nStarting time loop\n" << endl;

    while (runTime.run())
    {
        #include "readTimeControls.H"
        #include "interstitialCourantNo.H"
        #include "setAlphaDeltaT.H"

        // a collapsing time step means the coupling went unstable: stop
        // with the last written time as the last good state
        checkTimeStepCollapse
        (
            runTime, adjustTimeStep, maxDeltaT,
            "reduce maxDeltaT/maxCo/maxAlphaCo in system/controlDict."
        );

        // an absurd velocity (a diverged previous step, a bad initial
        // field) stops here with the cause, not in the linear solver
        grainCloud::checkFluidBlowUp(U, runTime.deltaTValue(), "fluid solve");

        ++runTime;
        Info<< "Time = " << runTime.timeName() << nl << endl;

        // 1. void fraction at the grains' current positions,
        // 2. semi-implicit drag prediction with the local mixture density
        //    and viscosity (p in Pa: the grains see the force -W grad(p))
        const clock::time_point t0 = clock::now();
        if (cloudPtr.valid())
        {
            vansCloud& cloud = cloudPtr();
            cloud.mapGrains();
            if (cloud.modelA())
            {
                pressureFactor = eps;
            }
            const volScalarField muMix("muMix", rho*mixture.nu());
            cloud.predictDrag(U, p, rho, muMix, runTime.deltaTValue());
            pK = pressureFactor + cloud.Kp();
            pK.correctBoundaryConditions();
        }
        const clock::time_point t1 = clock::now();

        // 3. fluid
        while (pimple.loop())
        {
            #include "alphaControls.H"
            #include "alphaEqnSubCycle.H"

            mixture.correct();

            #include "UEqn.H"

            while (pimple.correct())
            {
                #include "pEqn.H"
            }
        }

        const clock::time_point t2 = clock::now();

        // 4. fluid forces on the grains, 5. NSCD
        if (cloudPtr.valid())
        {
            vansCloud& cloud = cloudPtr();
            // a blown-up fluid stops here, before a grain step of ~forever
            grainCloud::checkFluidBlowUp(U, runTime.deltaTValue(), "grain step");
            cloud.setFluidForces(U, p);
            const clock::time_point t3 = clock::now();
            cloud.evolve(runTime.deltaTValue());
            timer.mapping += seconds(t2, t3);
            timer.contacts += seconds(t3, clock::now());
        }
        timer.mapping += seconds(t0, t1);
        timer.fluid += seconds(t1, t2);
        ++timer.steps;

        // water volume sum(eps alpha V) (conserved: closed domain)
        {
            const scalar waterVolume =
                gSum(eps.primitiveField()*alpha1.primitiveField()*mesh.V());
            std::ostringstream os;
            os.precision(17);
            os  << "water volume sum(eps alpha V) = " << waterVolume
                << " m^3, alpha min/max = " << gMin(alpha1.primitiveField())
                << " " << gMax(alpha1.primitiveField());
            Info<< os.str().c_str() << endl;
        }
        if (cloudPtr.valid())
        {
            Info<< "voidFraction min/max = " << gMin(eps.primitiveField())
                << " " << gMax(eps.primitiveField())
                << ", mean grain Reynolds number = "
                << cloudPtr->meanGrainReynolds()
                << ", max grain Reynolds number = "
                << cloudPtr->maxGrainReynolds() << endl;
        }

        // no NaN/Inf: stop before writing a bad state
        if
        (
            !std::isfinite(gSum(mag(U.primitiveField())))
         || !std::isfinite(gSum(mag(p_rgh.primitiveField())))
         || !std::isfinite(gSum(alpha1.primitiveField()))
        )
        {
            FatalErrorInFunction
                << "Non-finite velocity, pressure or phase fraction at time "
                << runTime.timeName() << ". The last written time holds the"
                << " last good state." << nl
                << "    Fix: reduce maxCo / maxAlphaCo / maxDeltaT in"
                << " system/controlDict." << exit(FatalError);
        }

        const bool go = runControl.writeStep
        (
            [&]()
            {
                if (cloudPtr.valid())
                {
                    cloudPtr->write();
                }
            }
        );
        if (!go)
        {
            break;
        }

        runTime.printExecutionTime(Info);
    }

    timer.report();

    Info<< "End\n" << endl;
    return 0;
}


// ************************************************************************* //
