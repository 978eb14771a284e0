// SPDX-License-Identifier: GPL-3.0-or-later
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
    forces on the grains -> NSCD step (grainMapping.H, fluidStep.H,
    grainStep.H; then the log and the finiteness checks, stepReport.H).
    Without constant/grainProperties there are no grains (eps = 1): the
    solver is then interFoam (laminar, static mesh, Euler).

    2D: one-cell-thick mesh with empty front/back (discs); 3D: spheres.
    Settings: constant/transportProperties (phases, sigma, phase rho/nu;
    rho, nu of the drag fluid when there are grains), constant/g, optional
    constant/grainProperties + constant/couplingProperties; alpha controls in
    system/fvSolution solvers.alpha.<phase1>.

Usage
    vansInterFoam [-parallel]
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "localMixtureFluidProperties.H"
#include "couplingStepTools.H"
#include "faceReconstruct.H"
#include "interfaceSnGrad.H"
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
#include "writeGridTime.H"
#include "wallFvPatch.H"

#include <sstream>
#include <unordered_map>

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
    #include "createWriteGridTime.H"
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
    #include "createStepFiles.H"

    #include "createCouplingStepTimer.H"

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
        #include "advanceCouplingTime.H"

        // 1. void fraction, 2. drag prediction (grains only; t0, t1)
        #include "grainMapping.H"
        // 3. fluid: PIMPLE (alpha, mixture, U, p_rgh) (t2)
        #include "fluidStep.H"
        // 4. fluid forces on the grains, 5. NSCD (grains only)
        #include "grainStep.H"
        #include "stepReport.H"

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

        timingFile.write
        (
            cloudPtr.valid() ? &cloudPtr->grains() : nullptr,
            scalarList({timer.mapping, timer.fluid, timer.contacts})
        );
        runTime.printExecutionTime(Info);
    }

    timer.report();

    Info<< "End\n" << endl;
    return 0;
}


// ************************************************************************* //
