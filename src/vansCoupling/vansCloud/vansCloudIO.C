// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud, restart state, output and start-up checks

Description
    The restart state read at the start (the void fraction of the start
    time; the grains' coupling state is in the grain state file, restart
    columns of vansCloud::declareGrainColumns, except for a state written
    by an older version: then from the per-grain lists it wrote,
    uniform/grainContactImpulse, grainDragImpulseDefect, grainHeldFraction,
    binary IOLists, one entry per grain in the order of the grain state,
    in the undecomposed case when the grains were decomposed; a list of
    another size is ignored), the grain output with the coupling fields,
    and the start-up warning about closed pores in 2D packings.
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "IOList.H"

// * * * * * * * * * * * * * * * Local Functions  * * * * * * * * * * * * * //

namespace
{
    //- <time>/uniform/<name>; grains decomposed: in the undecomposed
    //  case (an absolute instance)
    Foam::IOobject grainListIO
    (
        const Foam::grainCloud& grains,
        const Foam::word& name,
        const Foam::IOobject::readOption r
    )
    {
        using namespace Foam;
        const Time& runTime = grains.mesh().time();
        if (grains.decomposed())
        {
            return IOobject
            (
                name, runTime.globalPath()/runTime.timeName()/"uniform",
                grains.mesh(), r, IOobject::NO_WRITE, false
            );
        }
        return IOobject
        (
            name, runTime.timeName(), "uniform", grains.mesh(), r,
            IOobject::NO_WRITE, false
        );
    }

    //- Read <time>/uniform/<name> into column (one entry per grain of
    //  system()) if it exists with one entry per grain of the state;
    //  false (column unchanged) otherwise
    template<class Type>
    bool readGrainList
    (
        const Foam::grainCloud& grains,
        const Foam::word& name,
        Foam::UList<Type> column
    )
    {
        using namespace Foam;
        IOobject io(grainListIO(grains, name, IOobject::MUST_READ));
        if (!io.typeHeaderOk<IOList<Type>>(true))
        {
            return false;
        }
        const IOList<Type> read(io);
        if (grains.decomposed())
        {
            List<Type> local;
            if (!grains.fromStartOrder(read, local))
            {
                return false;
            }
            column.deepCopy(local);
            return true;
        }
        if (read.size() != label(grains.system().size()))
        {
            return false;
        }
        column.deepCopy(read);
        return true;
    }
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vansCloud::readRestart()
{
    // the void fraction written at a time is the "old" one of the next step
    IOobject epsIO
    (
        "voidFraction", mesh_.time().timeName(), mesh_, IOobject::MUST_READ
    );
    if (epsIO.typeHeaderOk<volScalarField>(true))
    {
        const volScalarField epsRead(epsIO, mesh_);
        voidFraction_.primitiveFieldRef() = epsRead.primitiveField();
        voidFraction_.correctBoundaryConditions();
    }
    voidFraction_.oldTime();
    // the restart columns were read with the grain state; a state written
    // by an older version lacks them: its per-grain lists
    if (!grains_.startStateHas(columns::contactImpulse))
    {
        readGrainList
        (
            grains_, columns::contactImpulse, vectors(columns::contactImpulse)
        );
    }
    if (!grains_.startStateHas(columns::dragImpulseDefect))
    {
        readGrainList
        (
            grains_, columns::dragImpulseDefect,
            vectors(columns::dragImpulseDefect)
        );
    }
    heldFractionSet_ =
        grains_.startStateHas(columns::heldFraction)
     || readGrainList
        (
            grains_, columns::heldFraction, scalars(columns::heldFraction)
        );
}


void Foam::vansCloud::warnClosedPores() const
{
    // 2D disc packings have closed pores (solid fraction ~0.82): without the
    // fluid-side effective diameter of thesis section 3.2.3 a settled bed of
    // fine grains gives cell void fractions < 0.1 and a stiff, unstable
    // coupling (applications/solvers/vansFoam/README.md, "Time step and
    // stability").  Cells more than half covered by ONE grain (a grain
    // larger than the cell: resolved or semi-resolved, eps -> epsMin there
    // by design) do not count: the warning is about packings of grains
    // smaller than the cells
    scalarField oneGrainShare(mesh_.nCells(), Zero);
    {
        const auto& ec = adapter_.entryCell();
        const auto& ev = adapter_.entryVolume();
        for (std::size_t e = 0; e < ec.size(); ++e)
        {
            const label c = ec[e];
            oneGrainShare[c] = max(oneGrainShare[c], ev[e]/mesh_.V()[c]);
        }
    }
    scalar epsLow = GREAT;
    forAll(oneGrainShare, c)
    {
        if (oneGrainShare[c] < 0.5)
        {
            epsLow = min(epsLow, voidFraction_[c]);
        }
    }
    reduce(epsLow, minOp<scalar>());
    const scalar kEff = adapter_.settings().effectiveDiameterFactor;
    if (adapter_.twoD() && kEff == 1 && epsLow < 0.1 && grains_.system().size())
    {
        WarningInFunction
            << "2D case with a void fraction down to " << epsLow
            << " at the start and voidFraction.effectiveDiameterFactor 1 in "
            << dict_.name() << ": discs pack to a solid fraction ~0.82 with"
            << " closed pores." << nl
            << "    Consider effectiveDiameterFactor ~0.88 (the solid fraction"
            << " of random sphere packings, thesis section 3.2.3); dense beds"
            << " of fine grains are otherwise unstable." << endl;
    }
}


void Foam::vansCloud::logSettings() const
{
    Info<< "vansCloud: force model " << settings_.forceModel;
    if (adapter_.twoD())
    {
        Info<< ", 2D drag convention " << drag_->discConventionName();
    }
    fluid_->describe(Info);
    if (rigidViscosity())
    {
        Info<< ", rigid viscosity ratio " << settings_.rigidViscosityRatio
            << " in resolved free grains";
    }
    if (undisturbed_.on())
    {
        Info<< ", undisturbed velocity " << undisturbed_.name()
            << " (self-induced velocity removed from the drag)";
    }
    Info<< ", rotation coupling " << (settings_.rotation ? "on" : "off")
        << ", void fraction min "
        << gMin(voidFraction_.primitiveField()) << nl << endl;
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vansCloud::write() const
{
    const label n = grains_.system().size();
    if (!fluidForcesSet_)
    {
        grains_.write();
        return;
    }
    // per-grain coupling output: fluid force and velocity; with rotation
    // the fluid torque `torqueFluid`; with heat the grain temperature `T`
    // and the gathered fluid temperature `Tfluid`
    const List<vector> F(vectors(columns::fluidForce));
    const List<vector> Uf(vectors(columns::fluidVelocity));
    const List<vector> torque(vectors(columns::fluidTorque));
    std::vector<std::pair<word, const List<vector>*>> outputs
    {
        {"Ffluid", &F}, {"Ufluid", &Uf}
    };
    if (settings_.rotation)
    {
        outputs.emplace_back("torqueFluid", &torque);
    }
    if (heatOn())
    {
        List<scalar> Tg(n);
        for (label i = 0; i < n; ++i)
        {
            Tg[i] = grains_.system().temperatures()[i];
        }
        List<scalar> Tf(heat_.Tfluid());
        Tf.setSize(n, Zero);
        grains_.write(outputs, {{"T", &Tg}, {"Tfluid", &Tf}});
    }
    else
    {
        grains_.write(outputs);
    }
}


// ************************************************************************* //
