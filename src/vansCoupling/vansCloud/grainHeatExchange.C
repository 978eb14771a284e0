// SPDX-License-Identifier: GPL-3.0-or-later
#include "grainHeatExchange.H"
#include "zeroGradientFvPatchFields.H"
#include "mathematicalConstants.H"

const Foam::word
    Foam::grainHeatExchange::TfluidColumn("vansFluidTemperature");


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::grainHeatExchange::grainHeatExchange
(
    const fvMesh& mesh,
    grainCloud& grains,
    const overlapMeshAdapter& adapter
)
:
    mesh_(mesh),
    grains_(grains),
    adapter_(adapter),
    KT_
    (
        IOobject("KT", mesh.time().timeName(), mesh),
        mesh,
        dimensionedScalar(inv(dimTime), Zero),
        zeroGradientFvPatchScalarField::typeName
    ),
    KTTp_
    (
        IOobject("KTTp", mesh.time().timeName(), mesh),
        mesh,
        dimensionedScalar(dimTemperature/dimTime, Zero),
        zeroGradientFvPatchScalarField::typeName
    )
{}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::grainHeatExchange::readProperties
(
    const IOdictionary& dict,
    const dictionary& td
)
{
    Cp_ = dimensionedScalar("Cp", dimSpecificHeatCapacity, td).value();
    kappa_ = dimensionedScalar
    (
        "kappa", dimPower/dimLength/dimTemperature, td
    ).value();
    beta_ =
        td.found("beta")
      ? dimensionedScalar("beta", inv(dimTemperature), td).value()
      : 0;
    TRef_ =
        td.found("TRef")
      ? dimensionedScalar("TRef", dimTemperature, td).value()
      : 0;
    if (!(Cp_ > 0) || !(kappa_ > 0))
    {
        FatalIOErrorInFunction(td)
            << "Cp and kappa in " << td.name() << " must be > 0 when"
            << " heatTransferModel is given in " << dict.name()
            << exit(FatalIOError);
    }
    const word form(td.getOrDefault<word>("energyForm", "advective"));
    if (form != "advective" && form != "conservative")
    {
        FatalIOErrorInFunction(td)
            << "energyForm " << form << " in " << td.name() << ": unknown."
            << nl << "    Fix: use advective (the default: the fluid"
            << " temperature stays within its initial and boundary values"
            << " where grains move) or conservative (eps T conserved"
            << " exactly, the thesis' eq. 4.4)." << exit(FatalIOError);
    }
    advectiveForm_ = form == "advective";
    if (beta_ != 0 && !td.found("TRef"))
    {
        FatalIOErrorInFunction(td)
            << "beta given without TRef in " << td.name()
            << ": the Boussinesq term eps g (1 - beta (T - TRef)) needs TRef"
            << exit(FatalIOError);
    }

    nscd::System& s = grains_.system();
    const label n = s.size();
    // every grain must integrate its temperature (heatCapacity > 0)
    for (label i = 0; i < n; ++i)
    {
        const nscd::Material& m = s.material(s.materials()[i]);
        if (!(m.heatCapacity > 0) && !s.fixedTemperature(i))
        {
            FatalErrorInFunction
                << "Grain " << i << " has material " << s.materials()[i]
                << " with heatCapacity 0 in the grain state, but heat transfer"
                << " is on (" << dict.name() << ")." << nl
                << "    Fix: give heatCapacity (and conductivity) to the"
                << " materials of " << grains_.dict().name()
                << " and re-run grainDeposit." << exit(FatalError);
        }
    }
    // initial temperatures: from the state file unless they are all 0 K
    // (a state never heated, e.g. from grainDeposit without
    // initialTemperature), then from grainProperties initialTemperature
    std::vector<double>& T = s.temperatures();
    bool allZero = true;
    for (label i = 0; i < n; ++i)
    {
        if (T[i] != 0) allZero = false;
    }
    if (grains_.decomposed())
    {
        reduce(allZero, andOp<bool>());   // (a rank may hold no grain)
    }
    if (n > 0 && allZero)
    {
        const dictionary& gd = grains_.dict();
        if (!gd.found("initialTemperature"))
        {
            FatalIOErrorInFunction(gd)
                << "Heat transfer is on (" << dict.name() << ") and the"
                << " grain state holds no temperatures (all 0 K): give"
                << " keyword initialTemperature [K] in " << gd.name()
                << exit(FatalIOError);
        }
        const scalar T0 = gd.get<scalar>("initialTemperature");
        for (label i = 0; i < n; ++i)
        {
            if (!s.fixedTemperature(i)) T[i] = T0;
        }
    }

    Hstar_.setSize(n, Zero);
    Tgrain0_.setSize(n, Zero);
    Qgrain_.setSize(n, Zero);
    grains_.addColumn<scalar>
    (
        TfluidColumn, nscd::ColumnMigrate | nscd::ColumnGhost, 0
    );
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainHeatExchange::read
(
    const IOdictionary& dict,
    const dictionary& td,
    const fluidProperties& fluid
)
{
    // absent or `none`: no fluid-grain heat exchange (KT, KTTp stay zero)
    if (dict.getOrDefault<word>("heatTransferModel", "none") == "none")
    {
        return;
    }
    if (!fluid.kinematic())
    {
        FatalIOErrorInFunction(dict)
            << "heatTransferModel in " << dict.name() << ": heat"
            << " transfer needs constant fluid properties (vansFoam)."
            << nl << "    Fix: remove heatTransferModel."
            << exit(FatalIOError);
    }
    rho_ = fluid.rho();
    nu_ = fluid.nu();
    model_ = heatTransferModel::New(dict);
    readProperties(dict, td);

    Info<< "vansCloud: heat transfer on, fluid Cp " << Cp_ << " kappa "
        << kappa_ << " Pr " << Cp_*rho_*nu_/kappa_ << ", energy equation in "
        << (advectiveForm_ ? "advective" : "conservative") << " form";
    if (beta_ != 0)
    {
        Info<< ", Boussinesq beta " << beta_ << " TRef " << TRef_;
    }
    Info<< endl;
}


void Foam::grainHeatExchange::predict
(
    const scalar dt,
    const volScalarField& voidFraction,
    const UList<scalar>& ReP
)
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    const label dim = s.dimension();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const scalar Pr = Cp_*rho_*nu_/kappa_;

    List<scalar> epsg;
    adapter_.gather(voidFraction, epsg);
    Hstar_.setSize(n);
    Tgrain0_.setSize(n);
    for (label i = 0; i < n; ++i)
    {
        const scalar r = s.radii()[i];
        const scalar d = 2*r;
        Tgrain0_[i] = s.temperatures()[i];
        if (!(W[i] > 0))
        {
            Hstar_[i] = 0;
            continue;
        }
        // true grain volume in mesh units (2D: disc area x mesh depth)
        const scalar V =
            dim == 3
          ? 4.0/3.0*constant::mathematical::pi*r*r*r
          : constant::mathematical::pi*r*r*depth;
        const scalar eps = max(epsg[i], adapter_.epsMin());
        const scalar Re = ReP.size() == n ? ReP[i] : scalar(0);
        const scalar H = V*model_->h(eps, Re, Pr, d, kappa_, dim);
        if (s.fixedTemperature(i))
        {
            Hstar_[i] = H;      // a heat bath: infinite capacity
            continue;
        }
        // grain heat capacity m c in mesh units (2D: nscd mass per depth)
        const scalar C =
            s.mass(i)*s.material(s.materials()[i]).heatCapacity*depth;
        Hstar_[i] = H*C/(C + dt*H);
    }

    scalarField& K = KT_.primitiveFieldRef();
    scalarField& KT = KTTp_.primitiveFieldRef();
    K = 0;
    KT = 0;
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    const auto& ev = adapter_.entryVolume();
    const scalar rhoCp = rho_*Cp_;
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        const label c = ec[e];
        const scalar a = ev[e]/W[gi]*Hstar_[gi]/rhoCp;
        K[c] += a;
        KT[c] += a*Tgrain0_[gi];
    }
    K /= mesh_.V();
    KT /= mesh_.V();
    KT_.correctBoundaryConditions();
    KTTp_.correctBoundaryConditions();
}


void Foam::grainHeatExchange::setSources
(
    const volScalarField& T,
    const scalar dt,
    const UList<scalar>& filmHeat
)
{
    nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    UList<scalar> Tf(Tfluid());
    {
        List<scalar> gathered;
        adapter_.gather(T, gathered);
        Tf.deepCopy(gathered);
    }
    Qgrain_.setSize(n);
    Qstep_ = 0;
    const bool film = filmHeat.size() == n;
    try
    {
        for (label i = 0; i < n; ++i)
        {
            if (s.fixedTemperature(i))
            {
                Qgrain_[i] = 0;
                continue;
            }
            // exactly the heat the fluid lost to grain i (the same weights
            // spread KT, KTTp and gather T)
            Qgrain_[i] = Hstar_[i]*(Tf[i] - Tgrain0_[i]);
            if (grains_.owned(i))
            {
                Qstep_ += dt*Qgrain_[i];
            }
            s.setHeatSource
            (
                i, Qgrain_[i]/depth + (film ? filmHeat[i] : scalar(0))
            );
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction << err.what() << exit(FatalError);
    }
    if (grains_.decomposed())
    {
        reduce(Qstep_, sumOp<scalar>());
    }
}


Foam::scalar Foam::grainHeatExchange::grainHeatContent() const
{
    return grains_.heatContent()*adapter_.depth();
}


Foam::scalar Foam::grainHeatExchange::grainMeanTemperature() const
{
    // every grain, fixed-temperature ones included
    return grains_.meanTemperature(false);
}


// ************************************************************************* //
