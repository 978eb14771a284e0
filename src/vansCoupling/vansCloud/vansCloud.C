#include "vansCloud.H"
#include "grainDictionaryTools.H"
#include "fvc.H"
#include "fixedValueFvPatchFields.H"
#include "zeroGradientFvPatchFields.H"
#include "uniformDimensionedFields.H"
#include "IOList.H"

// * * * * * * * * * * * * * * * Local Functions  * * * * * * * * * * * * * //

namespace
{
    //- fixedValue on every non-constraint patch (walls, inlets, ...): the
    //  solid flux through the domain boundary is zero, the void fraction 1
    Foam::wordList solidFluxPatchTypes(const Foam::fvMesh& mesh)
    {
        using namespace Foam;
        wordList types
        (
            mesh.boundary().size(),
            fixedValueFvPatchVectorField::typeName
        );
        forAll(mesh.boundary(), patchi)
        {
            const word& t = mesh.boundary()[patchi].patch().type();
            if (polyPatch::constraintType(t))
            {
                types[patchi] = t;
            }
        }
        return types;
    }

    Foam::IOobject fieldIO(const Foam::fvMesh& mesh, const Foam::word& name,
                           Foam::IOobject::writeOption w = Foam::IOobject::NO_WRITE)
    {
        return Foam::IOobject
        (
            name, mesh.time().timeName(), mesh, Foam::IOobject::NO_READ, w
        );
    }

    Foam::dictionary transportDict(const Foam::fvMesh& mesh)
    {
        using namespace Foam;
        IOdictionary d
        (
            IOobject
            (
                "transportProperties", mesh.time().constant(), mesh,
                IOobject::MUST_READ, IOobject::NO_WRITE, false
            )
        );
        return dictionary(d);
    }
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::vansCloud::vansCloud
(
    const fvMesh& mesh,
    const bool constantProperties
)
:
    mesh_(mesh),
    dict_
    (
        IOobject
        (
            "couplingProperties", mesh.time().constant(), mesh,
            IOobject::MUST_READ, IOobject::NO_WRITE
        )
    ),
    constantProperties_(constantProperties),
    rho_(0),
    nu_(0),
    rhoK_(1),
    rotation_(dict_.getOrDefault<bool>("rotationCoupling", false)),
    forceModel_(dict_.getOrDefault<word>("forceModel", "A")),
    maxDisplacementFraction_(0.1),
    grains_(mesh),
    adapter_
    (
        mesh,
        dict_.found("voidFraction") ? dict_.subDict("voidFraction") : dictionary::null
    ),
    drag_(nullptr),
    voidFraction_
    (
        fieldIO(mesh, "voidFraction", IOobject::AUTO_WRITE),
        mesh,
        dimensionedScalar("one", dimless, 1.0),
        // on the domain boundary the areal solid fraction of grains that do
        // not cross it is exactly 0: eps = 1 (an inlet then imposes the
        // superficial velocity U_b, whatever rests on it)
        solidFluxPatchTypes(mesh)
    ),
    Kdrag_
    (
        fieldIO(mesh, "Kdrag"), mesh, dimensionedScalar(inv(dimTime), Zero),
        zeroGradientFvPatchScalarField::typeName
    ),
    KUs_
    (
        fieldIO(mesh, "KUs"), mesh, dimensionedVector(dimAcceleration, Zero),
        zeroGradientFvPatchVectorField::typeName
    ),
    phiVs_
    (
        fieldIO(mesh, "phiVs"), mesh, dimensionedVector(dimVelocity, Zero),
        solidFluxPatchTypes(mesh)
    ),
    Ds_
    (
        fieldIO(mesh, "Ds"), mesh, dimensionedScalar(dimTime, Zero),
        solidFluxPatchTypes(mesh)
    ),
    Kp_
    (
        fieldIO(mesh, "Kp"), mesh, dimensionedScalar(dimless, Zero),
        zeroGradientFvPatchScalarField::typeName
    ),
    solidPressureForce_
    (
        fieldIO(mesh, "solidPressureForce"), mesh,
        dimensionedVector(dimAcceleration, Zero),
        zeroGradientFvPatchVectorField::typeName
    ),
    Bs_
    (
        fieldIO(mesh, "Bs"), mesh, dimensionedScalar(dimless, Zero),
        solidFluxPatchTypes(mesh)
    ),
    Kg_
    (
        fieldIO(mesh, "Kg"), mesh, dimensionedScalar(dimless, Zero),
        solidFluxPatchTypes(mesh)
    ),
    resolvedCellsPerDiameter_
    (
        // default: off (no grain resolved; see vansCloud.H, Resolved grains)
        dict_.getOrDefault<scalar>("resolvedCellsPerDiameter", GREAT)
    ),
    rigidViscosityRatio_
    (
        // default 1000, 0 with rotationCoupling (vansCloud.H, Resolved
        // grains: rigid interior, its limit for spin transients); only
        // used with resolved grains
        dict_.getOrDefault<scalar>("rigidViscosityRatio", rotation_ ? 0 : 1000)
    ),
    Br_
    (
        fieldIO(mesh, "Br"), mesh, dimensionedScalar(dimless, Zero),
        zeroGradientFvPatchScalarField::typeName
    ),
    KT_
    (
        fieldIO(mesh, "KT"), mesh, dimensionedScalar(inv(dimTime), Zero),
        zeroGradientFvPatchScalarField::typeName
    ),
    KTTp_
    (
        fieldIO(mesh, "KTTp"), mesh,
        dimensionedScalar(dimTemperature/dimTime, Zero),
        zeroGradientFvPatchScalarField::typeName
    )
{
    grainTools::checkKeywords
    (
        dict_,
        {
            "dragModel", "DallavalleDiFeliceCoeffs", "GidaspowCoeffs",
            "twoDimensionalDrag",
            "voidFraction", "forceModel",
            "heatTransferModel", "DiFeliceColburnCoeffs", "GunnCoeffs",
            "RanzMarshallCoeffs", "cohesion", "rotationCoupling",
            "resolvedCellsPerDiameter", "grainPorosity", "rigidViscosityRatio"
        }
    );
    grainPorosity_ = dict_.getOrDefault<scalar>("grainPorosity", 0);
    if (!(grainPorosity_ >= 0 && grainPorosity_ < 1))
    {
        FatalIOErrorInFunction(dict_)
            << "grainPorosity " << grainPorosity_ << " in " << dict_.name()
            << " must be >= 0 and < 1 (porosity n of the grains: the fluid"
            << " sees (1 - n) of each grain's volume, thesis 4.3.2)." << nl
            << "    Fix: e.g. grainPorosity 0.5; (default 0: solid grains)"
            << exit(FatalIOError);
    }
    if (!(resolvedCellsPerDiameter_ >= 0))
    {
        FatalIOErrorInFunction(dict_)
            << "resolvedCellsPerDiameter " << resolvedCellsPerDiameter_
            << " in " << dict_.name() << " must be >= 0." << nl
            << "    Fix: resolvedCellsPerDiameter 4; (grains spanning 4 or"
            << " more cells per diameter get the resolved solid flux, 0: all"
            << " grains; remove the keyword to switch it off)"
            << exit(FatalIOError);
    }
    if (!(rigidViscosityRatio_ >= 0))
    {
        FatalIOErrorInFunction(dict_)
            << "rigidViscosityRatio " << rigidViscosityRatio_
            << " in " << dict_.name() << " must be >= 0 (viscosity"
            << " nu (1 + lambda) inside resolved free grains)." << nl
            << "    Fix: rigidViscosityRatio 1000; (0: off)"
            << exit(FatalIOError);
    }
    if (forceModel_ != "A" && forceModel_ != "B")
    {
        FatalIOErrorInFunction(dict_)
            << "forceModel " << forceModel_ << " in " << dict_.name()
            << ": use A (eq. 3.23, -eps grad p in the fluid) or B (eq. 3.24)"
            << exit(FatalIOError);
    }
    drag_ = dragModel::New(dict_);

    const dictionary td(transportDict(mesh));
    if (constantProperties_)
    {
        rho_ = dimensionedScalar("rho", dimDensity, td).value();
        nu_ = dimensionedScalar("nu", dimViscosity, td).value();
        if (!(rho_ > 0) || !(nu_ > 0))
        {
            FatalIOErrorInFunction(td)
                << "rho and nu in constant/transportProperties must be > 0"
                << exit(FatalIOError);
        }
        rhoK_ = rho_;
    }
    else
    {
        // coupling fields per unit volume in dynamic units
        Kdrag_.dimensions().reset(dimDensity/dimTime);
        KUs_.dimensions().reset(dimForce/dimVolume);
        Ds_.dimensions().reset(dimVolume*dimTime/dimMass);
        solidPressureForce_.dimensions().reset(dimForce/dimVolume);
    }

    grains_.checkState();
    if (dict_.found("heatTransferModel"))
    {
        if (!constantProperties_)
        {
            FatalIOErrorInFunction(dict_)
                << "heatTransferModel in " << dict_.name() << ": heat"
                << " transfer needs constant fluid properties (vansFoam)."
                << nl << "    Fix: remove heatTransferModel."
                << exit(FatalIOError);
        }
        heat_ = heatTransferModel::New(dict_);
        readHeat(td);
    }
    readVapour(td);
    readCohesion();
    contactImpulse_.setSize(grains_.system().size(), Zero);
    dragImpulseDefect_.setSize(grains_.system().size(), Zero);

    // Restart: the void fraction and the grains' coupling state of the start
    // time (last contact impulses, the drag impulse the fluid still owes,
    // held fractions) make the next step identical to an uninterrupted run
    // (the void fraction written at a time is the "old" one of the next
    // step); a per-grain list is used only with one entry per grain
    IOobject epsIO
    (
        "voidFraction", mesh.time().timeName(), mesh, IOobject::MUST_READ
    );
    const label nGrains = grains_.system().size();
    auto readGrainList = [&](const word& name, auto& list)
    {
        using Type = typename std::decay_t<decltype(list)>::value_type;
        IOobject io
        (
            name, mesh.time().timeName(), "uniform", mesh,
            IOobject::MUST_READ, IOobject::NO_WRITE, false
        );
        if (io.typeHeaderOk<IOList<Type>>(true))
        {
            const IOList<Type> read(io);
            if (read.size() == nGrains)
            {
                list = read;
            }
        }
    };
    mapGrains();
    if (epsIO.typeHeaderOk<volScalarField>(true))
    {
        const volScalarField epsRead(epsIO, mesh);
        voidFraction_.primitiveFieldRef() = epsRead.primitiveField();
        voidFraction_.correctBoundaryConditions();
    }
    voidFraction_.oldTime();
    readGrainList("grainContactImpulse", contactImpulse_);
    readGrainList("grainDragImpulseDefect", dragImpulseDefect_);
    readGrainList("grainHeldFraction", heldFraction_);

    // 2D disc packings have closed pores (solid fraction ~0.82): without the
    // fluid-side effective diameter of thesis section 3.2.3 a settled bed of
    // fine grains gives cell void fractions < 0.1 and a stiff, unstable
    // coupling (applications/solvers/vansFoam/README.md, "Time step and
    // stability")
    // Cells more than half covered by ONE grain (a grain larger than the
    // cell: resolved or semi-resolved, eps -> epsMin there by design) do
    // not count: the warning is about packings of grains smaller than
    // the cells (a single resolved cylinder used to trigger it)
    scalarField oneGrainShare(mesh.nCells(), Zero);
    {
        const auto& ec = adapter_.entryCell();
        const auto& ev = adapter_.entryVolume();
        for (std::size_t e = 0; e < ec.size(); ++e)
        {
            const label c = ec[e];
            oneGrainShare[c] = max(oneGrainShare[c], ev[e]/mesh.V()[c]);
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

    Info<< "vansCloud: force model " << forceModel_;
    if (adapter_.twoD())
    {
        Info<< ", 2D drag convention " << drag_->discConventionName();
    }
    if (constantProperties_)
    {
        Info<< ", fluid rho " << rho_ << " nu " << nu_;
    }
    else
    {
        Info<< ", local fluid rho and mu (mixture fields)";
    }
    if (rigidViscosity())
    {
        Info<< ", rigid viscosity ratio " << rigidViscosityRatio_
            << " in resolved free grains";
    }
    Info<< ", rotation coupling " << (rotation_ ? "on" : "off")
        << ", void fraction min "
        << gMin(voidFraction_.primitiveField()) << nl << endl;
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vansCloud::readHeat(const dictionary& td)
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
            << " heatTransferModel is given in " << dict_.name()
            << exit(FatalIOError);
    }
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
                << " is on (" << dict_.name() << ")." << nl
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
    if (n > 0 && allZero)
    {
        const dictionary& gd = grains_.dict();
        if (!gd.found("initialTemperature"))
        {
            FatalIOErrorInFunction(gd)
                << "Heat transfer is on (" << dict_.name() << ") and the"
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
    Tfluid_.setSize(n, Zero);
    Qgrain_.setSize(n, Zero);

    Info<< "vansCloud: heat transfer on, fluid Cp " << Cp_ << " kappa "
        << kappa_ << " Pr " << Cp_*rho_*nu_/kappa_;
    if (beta_ != 0)
    {
        Info<< ", Boussinesq beta " << beta_ << " TRef " << TRef_;
    }
    Info<< endl;
}


void Foam::vansCloud::readVapour(const dictionary& td)
{
    if (!td.found("vapour"))
    {
        return;
    }
    if (!td.isDict("vapour"))
    {
        FatalIOErrorInFunction(td)
            << "vapour in " << td.name() << " must be a sub-dictionary"
            << " { D <D_v [m^2/s]>; rho <rho_v [kg/m^3]>; } (thesis eq. 4.19)"
            << exit(FatalIOError);
    }
    const dictionary& vd = td.subDict("vapour");
    grainTools::checkKeywords(vd, {"D", "rho", "bounded"});
    const char* keys[] = {"D", "rho"};
    const char* meaning[] =
    {
        "the vapour diffusion coefficient D_v [m^2/s], e.g. D 2.5e-5;",
        "the vapour density rho_v [kg/m^3], e.g. rho 0.6;"
    };
    for (label k = 0; k < 2; ++k)
    {
        if (!vd.found(keys[k]))
        {
            FatalIOErrorInFunction(vd)
                << "Missing keyword " << keys[k] << " in " << vd.name()
                << " (vapour transport, thesis eq. 4.19)." << nl
                << "    Fix: give " << meaning[k] << exit(FatalIOError);
        }
    }
    Dv_ = dimensionedScalar("D", dimViscosity, vd).value();
    rhov_ = dimensionedScalar("rho", dimDensity, vd).value();
    if (!(Dv_ >= 0) || !std::isfinite(Dv_))
    {
        FatalIOErrorInFunction(vd)
            << "D " << Dv_ << " in " << vd.name() << ": the vapour diffusion"
            << " coefficient must be >= 0 [m^2/s]" << exit(FatalIOError);
    }
    if (!(rhov_ > 0) || !std::isfinite(rhov_))
    {
        FatalIOErrorInFunction(vd)
            << "rho " << rhov_ << " in " << vd.name() << ": the vapour density"
            << " must be > 0 [kg/m^3]" << exit(FatalIOError);
    }
    vapourBounded_ = vd.getOrDefault<bool>("bounded", false);
    vapourOn_ = true;
    Info<< "vansCloud: vapour transport on, D_v " << Dv_ << " m^2/s, rho_v "
        << rhov_ << " kg/m^3, "
        << (vapourBounded_ ? "bounded (advective) form" : "conservative form")
        << endl;
}


void Foam::vansCloud::readCohesion()
{
    nscd::System& s = grains_.system();
    if (!dict_.found("cohesion"))
    {
        // a state written by a run with cohesion keeps its force: off here
        s.setCohesion(nullptr, 0);
        s.settings().cohesionMinAge = 0;
        return;
    }
    if (!dict_.isDict("cohesion"))
    {
        FatalIOErrorInFunction(dict_)
            << "cohesion in " << dict_.name() << " must be a sub-dictionary"
            << " { force <F_c0>; vapourThreshold <psi0>; minAge <steps>; }"
            << " (thesis eq. 4.18)" << exit(FatalIOError);
    }
    const dictionary& cd = dict_.subDict("cohesion");
    grainTools::checkKeywords(cd, {"force", "vapourThreshold", "minAge"});
    if (!cd.found("force"))
    {
        FatalIOErrorInFunction(cd)
            << "Missing keyword force in " << cd.name() << nl
            << "    Fix: give the cohesion force F_c0 of thesis eq. 4.18, in N"
            << " (3D) or N/m per unit depth (2D), e.g. force 0.2;"
            << exit(FatalIOError);
    }
    cohesionForce_ = grainTools::getPositive(cd, "force");
    cohesionMinAge_ = cd.getOrDefault<label>("minAge", 0);
    if (cohesionMinAge_ < 0)
    {
        FatalIOErrorInFunction(cd)
            << "minAge " << cohesionMinAge_ << " in " << cd.name()
            << ": the minimum contact age (NSCD steps) must be >= 0." << nl
            << "    Fix: minAge 0; (cohesive from the first step of contact)"
            << " or a number of steps the contact must persist"
            << exit(FatalIOError);
    }
    cohesionByVapour_ = cd.found("vapourThreshold");
    if (cohesionByVapour_)
    {
        vapourThreshold_ = cd.get<scalar>("vapourThreshold");
        if (!std::isfinite(vapourThreshold_))
        {
            FatalIOErrorInFunction(cd)
                << "vapourThreshold in " << cd.name() << " must be finite"
                << exit(FatalIOError);
        }
        if (!vapourOn_)
        {
            FatalIOErrorInFunction(cd)
                << "vapourThreshold in " << cd.name() << " switches cohesion"
                << " by the vapour field psi (thesis eq. 4.18), but vapour"
                << " transport is off." << nl
                << "    Fix: add vapour { D <m^2/s>; rho <kg/m^3>; } to"
                << " constant/transportProperties and the field 0/psi, or"
                << " remove vapourThreshold for cohesion everywhere (dry)."
                << exit(FatalIOError);
        }
    }

    s.settings().cohesionMinAge = cohesionMinAge_;
    cellHint_.setSize(s.size(), -1);
    try
    {
        if (cohesionByVapour_)
        {
            s.setCohesion
            (
                [this](int i, int j)
                {
                    const auto it = dryPairs_.find(pairKey(i, j));
                    return it != dryPairs_.end() && it->second;
                },
                cohesionForce_
            );
        }
        else
        {
            s.setCohesion([](int, int) { return true; }, cohesionForce_);
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction << err.what() << exit(FatalError);
    }
    Info<< "vansCloud: cohesion F_c0 " << cohesionForce_
        << (s.dimension() == 2 ? " N/m" : " N") << ", minAge "
        << cohesionMinAge_ << " steps, ";
    if (cohesionByVapour_)
    {
        Info<< "where psi < " << vapourThreshold_;
    }
    else
    {
        Info<< "everywhere (dry)";
    }
    Info<< endl;
}


void Foam::vansCloud::updateVapourCohesion()
{
    const word psiName("psi");
    if (!mesh_.foundObject<volScalarField>(psiName))
    {
        FatalErrorInFunction
            << "cohesion.vapourThreshold in " << dict_.name() << " needs the"
            << " vapour field " << psiName << ", which the solver has not"
            << " created." << nl << "    Fix: solve the vapour field (vansFoam"
            << " with transportProperties vapour {} and 0/psi)."
            << exit(FatalError);
    }
    const volScalarField& psi = mesh_.lookupObject<volScalarField>(psiName);
    const scalarField& psiI = psi.primitiveField();
    const nscd::System& s = grains_.system();
    const std::vector<nscd::System::ContactView> cs = s.contacts();
    const label nc = cs.size();
    const bool twoD = s.dimension() == 2;
    const overlapMapping::CellMesh& cm = adapter_.cellMesh();
    cellHint_.setSize(s.size(), -1);

    // 1 dry, 0 wet, -1 contact point not in a local cell
    labelList state(nc, -1);
    for (label k = 0; k < nc; ++k)
    {
        const nscd::System::ContactView& c = cs[k];
        const nscd::Vec3& xi = s.positions()[c.i];
        const scalar ri = s.radii()[c.i];
        nscd::Vec3 n = c.normal;
        scalar gap = c.gap;
        if (c.j >= 0)
        {
            // grain pair: line of centres at the current positions
            const nscd::Vec3 d = xi - s.positions()[c.j];
            const scalar dn = d.norm();
            if (dn > 0)
            {
                n = d/dn;
                gap = dn - ri - s.radii()[c.j];
            }
        }
        nscd::Vec3 p = xi - (ri + 0.5*gap)*n;
        if (twoD)
        {
            p.z() = grains_.meshPosition(c.i).z();
        }
        const label cell =
            cm.findCell(overlapMapping::Vec3(p.x(), p.y(), p.z()), cellHint_[c.i]);
        if (cell >= 0)
        {
            cellHint_[c.i] = cell;
            state[k] = psiI[cell] < vapourThreshold_ ? 1 : 0;
        }
    }
    if (Pstream::parRun())
    {
        // the same decision on every rank (the grains are advanced
        // identically everywhere): dry if dry where the point was found
        Pstream::listCombineGather(state, maxEqOp<label>());
        Pstream::listCombineScatter(state);
    }

    dryPairs_.clear();
    dryPairs_.reserve(2*nc);
    for (label k = 0; k < nc; ++k)
    {
        const bool dry = state[k] == 1;
        // several contacts of a grain with one wall (a crease): dry if all are
        const auto ins = dryPairs_.emplace(pairKey(cs[k].i, cs[k].j), dry);
        if (!ins.second)
        {
            ins.first->second = ins.first->second && dry;
        }
    }
    nDryPairs_ = 0;
    nWetPairs_ = 0;
    for (const auto& kv : dryPairs_)
    {
        ++(kv.second ? nDryPairs_ : nWetPairs_);
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vansCloud::mapGrains()
{
    if (grainPorosity_ > 0)
    {
        // porous grains (thesis 4.3.2): the fluid sees the concentric
        // disc/sphere of the solid volume (1 - n) V_p
        const nscd::System& s = grains_.system();
        const scalar k =
            adapter_.twoD()
          ? std::sqrt(1 - grainPorosity_)
          : std::cbrt(1 - grainPorosity_);
        const std::size_t n = s.size();
        std::vector<overlapMapping::Vec3> c(n);
        std::vector<double> r(n);
        for (std::size_t i = 0; i < n; ++i)
        {
            const nscd::Vec3& x = s.positions()[i];
            c[i] = overlapMapping::Vec3(x.x(), x.y(), x.z());
            r[i] = k*s.radii()[i];
        }
        adapter_.map(c.data(), r.data(), label(n));
    }
    else
    {
        adapter_.map(grains_.system());
    }
    adapter_.voidFraction(voidFraction_);
}


void Foam::vansCloud::predictDrag
(
    const volVectorField& U,
    const volScalarField& p,
    const scalar dt
)
{
    if (!constantProperties_)
    {
        FatalErrorInFunction
            << "vansCloud constructed without constant fluid properties:"
            << " call predictDrag(U, p, rho, mu, dt)" << exit(FatalError);
    }
    const label n = grains_.system().size();
    rhog_.setSize(n);
    nug_.setSize(n);
    rhog_ = rho_;
    nug_ = nu_;
    predictDragCore(U, fvc::grad(p)(), dt);
}


void Foam::vansCloud::predictDrag
(
    const volVectorField& U,
    const volScalarField& p,
    const volScalarField& rho,
    const volScalarField& mu,
    const scalar dt
)
{
    if (constantProperties_)
    {
        FatalErrorInFunction
            << "vansCloud constructed with constant fluid properties:"
            << " call predictDrag(U, p, dt) with the kinematic pressure"
            << exit(FatalError);
    }
    const label n = grains_.system().size();
    List<scalar> mug;
    adapter_.gather(rho, rhog_);
    adapter_.gather(mu, mug);
    nug_.setSize(n);
    forAll(nug_, i)
    {
        // a grain outside the mesh (W = 0) has no drag: any positive value
        if (!(rhog_[i] > 0) || !(mug[i] > 0))
        {
            rhog_[i] = 1;
            mug[i] = 1;
        }
        nug_[i] = mug[i]/rhog_[i];
    }
    predictDragCore(U, fvc::grad(p)(), dt);
}


void Foam::vansCloud::markResolved()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    resolved_.setSize(n);
    resolved_ = false;
    // without constant properties (vansInterFoam) the solver does not add
    // the B part of the solid flux: keep every grain unresolved
    if (!constantProperties_ || n == 0)
    {
        return;
    }
    const scalar depth = adapter_.depth();
    const bool twoD = adapter_.twoD();
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    List<scalar> hSum(n, Zero);
    List<scalar> nSum(n, Zero);
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const scalar Vc = mesh_.V()[ec[e]];
        hSum[eg[e]] += twoD ? std::sqrt(Vc/depth) : std::cbrt(Vc);
        nSum[eg[e]] += 1;
    }
    if (Pstream::parRun())
    {
        Pstream::listCombineGather(hSum, plusEqOp<scalar>());
        Pstream::listCombineScatter(hSum);
        Pstream::listCombineGather(nSum, plusEqOp<scalar>());
        Pstream::listCombineScatter(nSum);
    }
    for (label i = 0; i < n; ++i)
    {
        if (nSum[i] > 0)
        {
            const scalar h = hSum[i]/nSum[i];
            resolved_[i] = 2*s.radii()[i] >= resolvedCellsPerDiameter_*h;
        }
    }
}


void Foam::vansCloud::initHeldFraction()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    if (heldFraction_.size() == n)
    {
        return;
    }
    heldFraction_.setSize(n);
    heldFraction_ = 0;
    for (const nscd::System::ContactView& c : s.contacts())
    {
        if (c.impulse.squaredNorm() > 0)
        {
            heldFraction_[c.i] = 1;
            if (c.j >= 0)
            {
                heldFraction_[c.j] = 1;
            }
        }
    }
}


Foam::scalar Foam::vansCloud::fluidInverseMass(const label i) const
{
    // a held grain is seen 1e4 times heavier, not infinitely: where eps is
    // clipped at epsMin the drag coefficient is astronomical and gamma*
    // must stay bounded (<= 1e4 m/(W dt)) for a well-posed pressure equation
    const scalar theta = resolved_[i] ? 0 : heldFraction_[i];
    return (1 - theta*(1 - 1e-4))/grains_.system().mass(i);
}


bool Foam::vansCloud::fixedResolved() const
{
    const nscd::System& s = grains_.system();
    if (resolved_.size() != label(s.size()))
    {
        return false;
    }
    forAll(resolved_, i)
    {
        if (resolved_[i] && s.fixed(i))
        {
            return true;
        }
    }
    return false;
}


Foam::tmp<Foam::surfaceScalarField> Foam::vansCloud::rigidViscosityf() const
{
    const dimensionedScalar nu("nu", dimViscosity, nu_);
    // chi = max(0, 2 Br - 1): 0 in cells at most half covered, 1 in fully
    // covered ones, continuous in Br (smooth in time as the grain moves)
    const volScalarField chi(max(2*Br_ - 1, dimensionedScalar(dimless, Zero)));
    const volScalarField nuPen(nu*(1 + rigidViscosityRatio_*chi));
    // harmonic face mean (viscosities in series), minus the fluid's own nu,
    // clipped at 0 (round-off where neither cell is penalised)
    return max
    (
        1/fvc::interpolate(1/nuPen) - nu,
        dimensionedScalar(dimViscosity, Zero)
    );
}


Foam::vector Foam::vansCloud::leverArm(const std::size_t e) const
{
    const nscd::System& s = grains_.system();
    const label gi = adapter_.entryGrain()[e];
    const nscd::Vec3& x3 = s.positions()[gi];
    vector r = mesh_.C()[adapter_.entryCell()[e]] - vector(x3.x(), x3.y(), x3.z());
    if (adapter_.twoD())
    {
        r.z() = 0;
    }
    return r;
}


void Foam::vansCloud::predictDragCore
(
    const volVectorField& U,
    const volVectorField& gradp,
    const scalar dt
)
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();

    adapter_.gather(U, Ug_);
    adapter_.gather(voidFraction_, epsg_);
    adapter_.gather(gradp, gradpg_);

    dt_ = dt;
    gamma_.setSize(n);
    gammaStar_.setSize(n);
    vss_.setSize(n);
    vStar_.setSize(n);
    ReP_.setSize(n);

    const nscd::Vec3& g3 = s.gravity();
    const vector g(g3.x(), g3.y(), g3.z());
    const std::vector<double>& W = adapter_.grainMappedVolume();
    markResolved();
    initHeldFraction();

    for (label i = 0; i < n; ++i)
    {
        const nscd::Vec3& v3 = s.velocities()[i];
        const vector v(v3.x(), v3.y(), v3.z());
        const scalar d = 2*s.radii()[i];
        const scalar slip = mag(Ug_[i] - v);
        ReP_[i] = slip*d/nug_[i];
        const scalar eps = max(epsg_[i], adapter_.epsMin());
        gamma_[i] =
            W[i] > 0
          ? drag_->gamma
            (
                eps, ReP_[i], d, rhog_[i]*nug_[i], rhog_[i], adapter_.twoD()
            )
          : 0;

        if (s.fixed(i))
        {
            gammaStar_[i] = gamma_[i];
            vss_[i] = v;
            vStar_[i] = v;
            continue;
        }
        const scalar m = s.mass(i);
        const scalar im = fluidInverseMass(i);
        const scalar Wdg = W[i]/depth*dt*gamma_[i];
        // v**_0: v** without its (implicit) pressure-gradient part
        vss_[i] = v + im*(m*dt*g + contactImpulse_[i]);
        gammaStar_[i] = gamma_[i]/(1 + Wdg*im);
        vStar_[i] = (vss_[i] + Wdg*im*Ug_[i])/(1 + Wdg*im);
    }

    // Drag fields: K = sum (V_pc/V_c) gamma*/rho, K v**, and for model B
    // the solid part of the pressure force phi grad(p)
    scalarField& K = Kdrag_.primitiveFieldRef();
    vectorField& KU = KUs_.primitiveFieldRef();
    vectorField& sp = solidPressureForce_.primitiveFieldRef();
    scalarField& D = Ds_.primitiveFieldRef();
    scalarField& Kp = Kp_.primitiveFieldRef();
    scalarField& B = Bs_.primitiveFieldRef();
    scalarField& Kg = Kg_.primitiveFieldRef();
    scalarField& Br = Br_.primitiveFieldRef();
    Br = 0;
    Kg = 0;
    K = 0;
    KU = Zero;
    sp = Zero;
    D = 0;
    Kp = 0;
    B = 0;
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    const auto& ev = adapter_.entryVolume();
    if (rotation_)
    {
        omega_.setSize(n);
        for (label i = 0; i < n; ++i)
        {
            const nscd::Vec3& w = s.angularVelocities()[i];
            omega_[i] = vector(w.x(), w.y(), w.z());
        }
    }
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        const label c = ec[e];
        K[c] += ev[e]*gammaStar_[gi]/rhoK_;
        if (rotation_)
        {
            // rigid-body velocity of the grain at the cell (resolved
            // regime: Brinkman penalisation of translation and rotation)
            KU[c] +=
                ev[e]*gammaStar_[gi]/rhoK_
               *(vss_[gi] + (omega_[gi] ^ leverArm(e)));
        }
        else
        {
            KU[c] += ev[e]*gammaStar_[gi]/rhoK_*vss_[gi];
        }
        sp[c] += ev[e]*gradpg_[gi];
        if (!s.fixed(gi))
        {
            const scalar im = fluidInverseMass(gi);
            const scalar Wi = W[gi]/depth;
            // the drag impulse the grain received beyond what the fluid gave
            // last step, taken from the fluid now (its share V_pc/W_p)
            if (dragImpulseDefect_.size() == n)
            {
                KU[c] -= ev[e]*dragImpulseDefect_[gi]/(Wi*dt*rhoK_);
            }
            D[c] += ev[e]*Wi*dt*rhoK_*im/(1 + Wi*dt*gamma_[gi]*im);
            Kp[c] += ev[e]*gammaStar_[gi]*Wi*dt*im;
            if (resolved_[gi])
            {
                // (never held: im = 1/m)
                B[c] += ev[e]*Wi*dt*gamma_[gi]*im/(1 + Wi*dt*gamma_[gi]*im);
                Kg[c] += ev[e]*gammaStar_[gi]*dt/rhoK_;
                Br[c] += ev[e];
            }
        }
    }
    K /= mesh_.V();
    KU /= mesh_.V();
    sp /= mesh_.V();
    D /= mesh_.V();
    Kp /= mesh_.V();
    B /= mesh_.V();
    Kg /= mesh_.V();
    Br /= mesh_.V();
    Br_.correctBoundaryConditions();
    Bs_.correctBoundaryConditions();
    Kg_.correctBoundaryConditions();
    Ds_.correctBoundaryConditions();
    Kp_.correctBoundaryConditions();
    Kdrag_.correctBoundaryConditions();
    KUs_.correctBoundaryConditions();
    solidPressureForce_.correctBoundaryConditions();
}


Foam::tmp<Foam::surfaceScalarField> Foam::vansCloud::solidFlux
(
    const volVectorField& U,
    const scalar dt
)
{
    const nscd::System& s = grains_.system();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    adapter_.gather(U, Ug_);
    for (label i = 0; i < label(s.size()); ++i)
    {
        if (s.fixed(i)) continue;
        const scalar im = fluidInverseMass(i);
        const scalar Wdg = W[i]/depth*dt*gamma_[i];
        // resolved grain: only the v** part, a_p v**_0; its fluid part
        // b_p U is added per cell with the cell's own, pressure-dependent
        // velocity by the solver (B_f, pEqn.H)
        const scalar b =
            resolved_.size() == label(s.size()) && resolved_[i]
          ? 0 : Wdg*im;
        vStar_[i] = (vss_[i] + b*Ug_[i])/(1 + Wdg*im);
    }
    if (!rotation_)
    {
        adapter_.solidVelocity(vStar_, phiVs_);
    }
    else
    {
        // the rigid-body velocity v*_p + omega_p x r_pc per overlap entry:
        // the mixture flux eps U + phi v_s is then divergence free where the
        // penalisation imposes U = v_s (a rotating grain in cells of varying
        // eps), as for the translation
        vectorField& f = phiVs_.primitiveFieldRef();
        f = Zero;
        const auto& eg = adapter_.entryGrain();
        const auto& ec = adapter_.entryCell();
        const auto& ev = adapter_.entryVolume();
        for (std::size_t e = 0; e < ec.size(); ++e)
        {
            const label gi = eg[e];
            // resolved grain: a_p (v**_0 + omega x r), the b_p part comes
            // with the local fluid velocity (which the penalisation drives
            // to v** + omega x r)
            scalar a = 1;
            if (!s.fixed(gi) && resolved_.size() == label(s.size()) && resolved_[gi])
            {
                const scalar Wdg = W[gi]/depth*dt*gamma_[gi];
                a = 1/(1 + Wdg*fluidInverseMass(gi));
            }
            f[ec[e]] +=
                ev[e]*(vStar_[gi] + a*(omega_[gi] ^ leverArm(e)));
        }
        f /= mesh_.V();
        phiVs_.correctBoundaryConditions();
    }
    return fvc::flux(phiVs_);
}


void Foam::vansCloud::setFluidForces
(
    const volVectorField& U,
    const volScalarField& p
)
{
    nscd::System& s = grains_.system();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    adapter_.gather(U, Ug_);
    const volVectorField gradp(fvc::grad(p));
    adapter_.gather(gradp, gradpg_);
    const label nGrains = s.size();
    fluidForce_.setSize(nGrains);
    explicitFluidForce_.setSize(nGrains);
    fluidDragGiven_.setSize(nGrains);
    fluidVelocity_ = Ug_;
    for (label i = 0; i < nGrains; ++i)
    {
        const scalar Wi = W[i]/depth;
        // v** with the final pressure gradient (eq. 3.47)
        const vector vss =
            s.fixed(i)
          ? vss_[i]
          : vss_[i] - (dt_*Wi*fluidInverseMass(i)*rhoK_)*gradpg_[i];
        // the drag the fluid took from its own equation, W gamma (U - v*)
        // with the predicted v* (eq. 3.48); the grains get W gamma (U - v)
        // with their velocity after the contact solve (evolve)
        const vector drag = Wi*gammaStar_[i]*(Ug_[i] - vss);
        explicitFluidForce_[i] = -Wi*rhoK_*gradpg_[i];
        fluidForce_[i] = explicitFluidForce_[i] + drag;
        fluidDragGiven_[i] = dt_*drag;
    }
    if (!rotation_)
    {
        applyGrainForces(UList<vector>());
        return;
    }

    // Rotation: per overlap entry the force on the grain is
    //   f_pc = (V_pc/depth)(-rho grad(p)_c
    //          + gamma*_p (U_c - v**_p(c) - omega_p x r_pc))
    // with v**_p(c) = v**_0 - (W dt/m) rho grad(p)_c: summed over c it is
    // F_p above (the gather weights are V_pc/W_p) plus the rotational part
    // -gamma* omega x sum V_pc r_pc; the torque is sum r_pc x f_pc, explicit
    // for the next NSCD step.  The fluid lost exactly sum f_pc at the cell
    // centres x_p + r_pc: angular momentum is exchanged exactly.
    const label n = s.size();
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    const auto& ev = adapter_.entryVolume();
    const vectorField& UI = U.primitiveField();
    const vectorField& gI = gradp.primitiveField();
    List<vector> Frot(n, Zero);
    fluidTorque_.setSize(n);
    fluidTorque_ = Zero;
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        const label c = ec[e];
        const vector r = leverArm(e);
        const scalar cp = s.fixed(gi) ? 0 : dt_*W[gi]/depth*fluidInverseMass(gi)*rhoK_;
        const vector vs = vss_[gi] - cp*gI[c] + (omega_[gi] ^ r);
        const vector f =
            ev[e]/depth*(-rhoK_*gI[c] + gammaStar_[gi]*(UI[c] - vs));
        fluidTorque_[gi] += r ^ f;
        Frot[gi] -= ev[e]/depth*gammaStar_[gi]*(omega_[gi] ^ r);
    }
    if (Pstream::parRun())
    {
        Pstream::listCombineGather(fluidTorque_, plusEqOp<vector>());
        Pstream::listCombineScatter(fluidTorque_);
        Pstream::listCombineGather(Frot, plusEqOp<vector>());
        Pstream::listCombineScatter(Frot);
    }

    // drag angular momentum exchange about the origin (mesh units):
    // the grains gain sum_p x_p x F^drag_p + T^drag_p, the fluid loses
    // sum_c V_c x_c x rho (K U - K v_s)_c
    dragTorqueGrains_ = Zero;
    for (label i = 0; i < n; ++i)
    {
        // the rotational drag -gamma* omega x sum V_pc r_pc: explicit
        fluidForce_[i] += Frot[i];
        explicitFluidForce_[i] += Frot[i];
        if (adapter_.twoD())
        {
            fluidTorque_[i].x() = 0;
            fluidTorque_[i].y() = 0;
        }
    }
    applyGrainForces(UList<vector>());
    // the drag part only (pressure excluded), from the per-entry forces
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        const label c = ec[e];
        const nscd::Vec3& x3 = s.positions()[gi];
        vector xc = mesh_.C()[c];
        if (adapter_.twoD())
        {
            xc.z() = x3.z();
        }
        const scalar cp = s.fixed(gi) ? 0 : dt_*W[gi]/depth*fluidInverseMass(gi)*rhoK_;
        const vector vs = vss_[gi] - cp*gI[c] + (omega_[gi] ^ leverArm(e));
        dragTorqueGrains_ += xc ^ (ev[e]*gammaStar_[gi]*(UI[c] - vs));
    }
    // fluid side from the fields (K U - K v**_0 + K_p rho grad p): the
    // pressure part of v** enters the fluid through K_p
    dragTorqueFluid_ = Zero;
    const vectorField& KU = KUs_.primitiveField();
    const scalarField& K = Kdrag_.primitiveField();
    const scalarField& Kp = Kp_.primitiveField();
    forAll(K, c)
    {
        vector xc = mesh_.C()[c];
        const vector f =
            mesh_.V()[c]*rhoK_*(K[c]*UI[c] - KU[c] + Kp[c]*gI[c]);
        dragTorqueFluid_ += xc ^ f;
    }
    reduce(dragTorqueGrains_, sumOp<vector>());
    reduce(dragTorqueFluid_, sumOp<vector>());
    if (adapter_.twoD())
    {
        // about the z axis through the origin; the in-plane components
        // carry the arbitrary z of the cell centres
        dragTorqueGrains_.x() = dragTorqueGrains_.y() = 0;
        dragTorqueFluid_.x() = dragTorqueFluid_.y() = 0;
    }
    scalar Tmax = 0;
    forAll(fluidTorque_, i) Tmax = max(Tmax, mag(fluidTorque_[i]));
    Info<< "rotationCoupling: max |fluid torque| " << Tmax
        << ", drag angular momentum rate lost by the fluid "
        << dragTorqueFluid_.z() << " gained by the grains "
        << dragTorqueGrains_.z() << endl;
}


void Foam::vansCloud::addExternalForces(const UList<vector>& F)
{
    const label n = grains_.system().size();
    if (F.empty())
    {
        return;
    }
    if (F.size() != n || explicitFluidForce_.size() != n)
    {
        FatalErrorInFunction
            << "addExternalForces: " << F.size() << " forces for " << n
            << " grains (" << explicitFluidForce_.size() << " fluid forces):"
            << " call it after setFluidForces with one force per grain."
            << exit(FatalError);
    }
    applyGrainForces(F);
}


void Foam::vansCloud::applyGrainForces(const UList<vector>& extra)
{
    nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const bool torque = rotation_ && fluidTorque_.size() == n;
    for (label i = 0; i < n; ++i)
    {
        vector F = explicitFluidForce_[i];
        if (extra.size() == n)
        {
            F += extra[i];
        }
        const vector T = torque ? fluidTorque_[i] : vector(Zero);
        const vector& u = fluidVelocity_[i];
        s.setExternalForce
        (
            i,
            nscd::Vec3(F.x(), F.y(), F.z()),
            nscd::Vec3(T.x(), T.y(), T.z())
        );
        // drag coefficient W gamma [kg/s] (2D: per unit depth)
        s.setFluidDrag
        (
            i,
            s.fixed(i) ? 0.0 : W[i]/depth*gamma_[i],
            nscd::Vec3(u.x(), u.y(), u.z())
        );
    }
}


void Foam::vansCloud::evolve(const scalar dt)
{
    nscd::System& s = grains_.system();
    label n = s.size();
    List<vector> v0(n);
    for (label i = 0; i < n; ++i)
    {
        const nscd::Vec3& v = s.velocities()[i];
        v0[i] = vector(v.x(), v.y(), v.z());
    }

    if (cohesionByVapour_)
    {
        updateVapourCohesion();
    }

    grains_.evolve(dt);
    if (grains_.removedGrains().size())   // grains left through outlets
    {
        grains_.compactRemoved(v0);
        compactRemovedGrains();
        n = s.size();
    }

    if (cohesionOn())
    {
        Info<< "cohesion: cohesive contacts " << grains_.report().cohesiveContacts
            << " of " << s.nContacts();
        if (cohesionByVapour_)
        {
            Info<< ", pairs looked up dry " << nDryPairs_ << " wet "
                << nWetPairs_;
        }
        Info<< endl;
    }

    // Contact impulse of the whole step (all sub-steps), p^n of eq. 3.46:
    // what changed the momentum besides gravity and the fluid force; the
    // fluid force actually received (explicit part + the drag impulse of
    // the contact solve) and the drag impulse the fluid still owes
    const nscd::Vec3& g3 = s.gravity();
    const vector g(g3.x(), g3.y(), g3.z());
    const std::vector<nscd::Vec3>& J = s.fluidDragImpulses();
    const bool coupled =
        explicitFluidForce_.size() == n && fluidDragGiven_.size() == n
     && fluidForce_.size() == n;
    dragImpulseDefect_.setSize(n);
    heldFraction_.setSize(n);
    for (label i = 0; i < n; ++i)
    {
        dragImpulseDefect_[i] = Zero;
        if (s.fixed(i))
        {
            heldFraction_[i] = 0;
            contactImpulse_[i] = Zero;
            continue;
        }
        const nscd::Vec3& v = s.velocities()[i];
        const scalar m = s.mass(i);
        const vector Jd(J[i].x(), J[i].y(), J[i].z());
        // rotation on: F0 includes the rotational drag part
        const vector F0 = coupled ? explicitFluidForce_[i] : vector::zero;
        contactImpulse_[i] =
            m*(vector(v.x(), v.y(), v.z()) - v0[i]) - dt*(m*g + F0) - Jd;
        if (coupled)
        {
            fluidForce_[i] = F0 + Jd/dt;
            dragImpulseDefect_[i] = Jd - fluidDragGiven_[i];
        }
        // held fraction: how much of the free drift P the contacts cancelled
        const vector u = fluidVelocity_.size() == n ? fluidVelocity_[i] : v0[i];
        const vector P =
            dt*(m*g + F0 + s.fluidDragCoefficient(i)*(u - v0[i]));
        const scalar P2 = magSqr(P);
        heldFraction_[i] =
            P2 > 0 ? min(max(-(contactImpulse_[i] & P)/P2, scalar(0)), scalar(1)) : 0;
    }
}


void Foam::vansCloud::predictHeat(const scalar dt)
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    const label dim = s.dimension();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const scalar Pr = Cp_*rho_*nu_/kappa_;

    adapter_.gather(voidFraction_, epsg_);
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
        const scalar eps = max(epsg_[i], adapter_.epsMin());
        const scalar Re = ReP_.size() == n ? ReP_[i] : scalar(0);
        const scalar H = V*heat_->h(eps, Re, Pr, d, kappa_, dim);
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


void Foam::vansCloud::setHeatSources(const volScalarField& T, const scalar dt)
{
    nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    adapter_.gather(T, Tfluid_);
    Qgrain_.setSize(n);
    Qstep_ = 0;
    // heat into the grains from an immersed droplet's Leidenfrost film
    // (dropletCoupling, IOField dropletGrainHeat, nscd units: W/m in 2D;
    // absent or empty: none); not part of the fluid-grain exchange
    const IOField<scalar>* filmHeat =
        mesh_.foundObject<IOField<scalar>>("dropletGrainHeat")
      ? &mesh_.lookupObject<IOField<scalar>>("dropletGrainHeat")
      : nullptr;
    if (filmHeat && filmHeat->size() != n)
    {
        filmHeat = nullptr;
    }
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
            Qgrain_[i] = Hstar_[i]*(Tfluid_[i] - Tgrain0_[i]);
            Qstep_ += dt*Qgrain_[i];
            s.setHeatSource
            (
                i, Qgrain_[i]/depth + (filmHeat ? (*filmHeat)[i] : scalar(0))
            );
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction << err.what() << exit(FatalError);
    }
}


Foam::scalar Foam::vansCloud::grainHeatContent() const
{
    return grains_.system().heatContent()*adapter_.depth();
}


Foam::scalar Foam::vansCloud::grainMeanTemperature() const
{
    const std::vector<double>& T = grains_.system().temperatures();
    scalar sum = 0;
    for (const double t : T) sum += t;
    return T.empty() ? 0 : sum/T.size();
}


Foam::scalar Foam::vansCloud::maxGrainReynolds() const
{
    return ReP_.empty() ? 0 : max(ReP_);
}


Foam::scalar Foam::vansCloud::meanGrainReynolds() const
{
    return ReP_.empty() ? 0 : sum(ReP_)/ReP_.size();
}


void Foam::vansCloud::write() const
{
    // the grains' coupling state for the exact restart (read back by the
    // constructor), binary
    auto writeGrainList = [this](const word& name, const auto& list)
    {
        using Type = typename std::decay_t<decltype(list)>::value_type;
        IOList<Type> io
        (
            IOobject
            (
                name, mesh_.time().timeName(), "uniform",
                mesh_, IOobject::NO_READ, IOobject::NO_WRITE, false
            ),
            list
        );
        io.writeObject
        (
            IOstream::BINARY, IOstream::currentVersion,
            IOstream::UNCOMPRESSED, true
        );
    };
    writeGrainList("grainContactImpulse", contactImpulse_);
    writeGrainList("grainDragImpulseDefect", dragImpulseDefect_);
    if (heldFraction_.size())
    {
        writeGrainList("grainHeldFraction", heldFraction_);
    }
    const label n = grains_.system().size();
    if (fluidForce_.size() != n || fluidVelocity_.size() != n)
    {
        grains_.write();
        return;
    }
    // per-grain coupling output: fluid force and velocity; with rotation
    // the fluid torque `torqueFluid`; with heat the grain temperature `T`
    // and the gathered fluid temperature `Tfluid`
    std::vector<std::pair<word, const List<vector>*>> vectors
    {
        {"Ffluid", &fluidForce_}, {"Ufluid", &fluidVelocity_}
    };
    if (rotation_ && fluidTorque_.size() == n)
    {
        vectors.emplace_back("torqueFluid", &fluidTorque_);
    }
    if (heatOn())
    {
        List<scalar> Tg(n);
        for (label i = 0; i < n; ++i)
        {
            Tg[i] = grains_.system().temperatures()[i];
        }
        List<scalar> Tf(Tfluid_);
        Tf.setSize(n, Zero);
        grains_.write(vectors, {{"T", &Tg}, {"Tfluid", &Tf}});
    }
    else
    {
        grains_.write(vectors);
    }
}
