// SPDX-License-Identifier: GPL-3.0-or-later
#include "vansCloud.H"
#include "foamTools.H"
#include "fvc.H"
#include "fixedValueFvPatchFields.H"
#include "zeroGradientFvPatchFields.H"
#include "calculatedFvPatchFields.H"
#include "constantFluidProperties.H"

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

    Foam::IOobject fieldIO
    (
        const Foam::fvMesh& mesh,
        const Foam::word& name,
        Foam::IOobject::writeOption w = Foam::IOobject::NO_WRITE
    )
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

    //- The fluid properties handed to the constructor; FatalError if null
    const Foam::fluidProperties& validFluid
    (
        const Foam::autoPtr<Foam::fluidProperties>& fluid
    )
    {
        if (!fluid.valid())
        {
            FatalErrorInFunction
                << "vansCloud constructed without fluid properties"
                << Foam::exit(Foam::FatalError);
        }
        return *fluid;
    }
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::vansCloud::vansCloud(const fvMesh& mesh)
:
    vansCloud
    (
        mesh,
        autoPtr<fluidProperties>
        (
            new constantFluidProperties(transportDict(mesh))
        )
    )
{}


Foam::vansCloud::vansCloud
(
    const fvMesh& mesh,
    autoPtr<fluidProperties> fluid
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
    settings_(dict_),
    fluid_(std::move(fluid)),
    grains_
    (
        // every sub-model makes its per-grain sums over the grains' copies
        // on several ranks (vansFoam and vansInterFoam): the grains may be
        // decomposed (grainProperties grainDecomposition)
        mesh, true, string(),
        &vansCloud::declareGrainColumns
    ),
    adapter_
    (
        mesh,
        dict_.found("voidFraction")
      ? dict_.subDict("voidFraction")
      : dictionary::null
    ),
    drag_(nullptr),
    undisturbed_(dict_, adapter_.twoD()),
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
    // the boundary values are assigned with the internal ones (pf + K_p on
    // every patch): calculated patches
    pressureCoefficient_
    (
        fieldIO(mesh, "pressureCoefficient"), mesh,
        dimensionedScalar("one", dimless, 1.0),
        calculatedFvPatchScalarField::typeName
    ),
    solidPressureForce_
    (
        fieldIO(mesh, "solidPressureForce"), mesh,
        dimensionedVector(dimAcceleration, Zero),
        zeroGradientFvPatchVectorField::typeName
    ),
    resolved_
    (
        mesh, grains_, adapter_, settings_, validFluid(fluid_),
        solidFluxPatchTypes(mesh)
    ),
    heat_(mesh, grains_, adapter_),
    cohesion_(mesh, grains_, adapter_)
{
    drag_ = dragModel::New(dict_);

    const dictionary td(transportDict(mesh));
    if (!fluid_->kinematic())
    {
        // coupling fields per unit volume in dynamic units
        Kdrag_.dimensions().reset(dimDensity/dimTime);
        KUs_.dimensions().reset(dimForce/dimVolume);
        Ds_.dimensions().reset(dimVolume*dimTime/dimMass);
        solidPressureForce_.dimensions().reset(dimForce/dimVolume);
    }

    grains_.checkState();
    readSubModels(td);
    if (grains_.decomposed())
    {
        // the grains' overlap sums over several ranks' cells are completed
        // over the grains' copies (owned and ghosts)
        adapter_.setDecomposedGrains
        (
            [this](std::vector<double>& values, int components)
            {
                grains_.sumOverCopies(values, components);
            }
        );
    }
    mapGrains();
    readRestart();
    warnClosedPores();

    logSettings();
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vansCloud::readSubModels(const dictionary& transport)
{
    heat_.read(dict_, transport, *fluid_);
    const vapourSettings& vap = settings_.vapour;
    settings_.vapour.read(transport);
    if (vap.on)
    {
        Info<< "vansCloud: vapour transport on, D_v " << vap.D
            << " m^2/s, rho_v " << vap.rho << " kg/m^3, "
            << (vap.bounded ? "bounded (advective) form" : "conservative form")
            << endl;
    }
    cohesion_.read(dict_, vap.on);
}


void Foam::vansCloud::predictGrains
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
    UList<scalar> ReP(scalars(columns::grainReynolds));

    const vector g(foamTools::toVector(s.gravity()));
    const std::vector<double>& W = adapter_.grainMappedVolume();
    resolved_.mark();
    initHeldFraction();
    const UList<scalar> held(scalars(columns::heldFraction));
    const UList<vector> contactImpulse(vectors(columns::contactImpulse));

    undisturbed_.updateKernelWidths(mesh_, adapter_);

    for (label i = 0; i < n; ++i)
    {
        const vector v(foamTools::toVector(s.velocities()[i]));
        const scalar d = 2*s.radii()[i];
        const scalar slip = mag(Ug_[i] - v);
        ReP[i] = slip*d/nug_[i];
        const scalar eps = max(epsg_[i], adapter_.epsMin());
        const scalar mu = rhog_[i]*nug_[i];
        if (!(W[i] > 0))
        {
            gamma_[i] = 0;
        }
        else if (undisturbed_.on())
        {
            // the drag law at the undisturbed slip (ReP becomes its
            // Reynolds number), coefficient gamma/(1 - kappa) on u_g - v
            gamma_[i] = undisturbed_.gamma
            (
                i, drag_(), eps, ReP[i], d, mu, rhog_[i], W[i], ReP[i]
            );
        }
        else
        {
            gamma_[i] =
                drag_->gamma(eps, ReP[i], d, mu, rhog_[i], adapter_.twoD());
        }

        if (s.fixed(i))
        {
            gammaStar_[i] = gamma_[i];
            vss_[i] = v;
            vStar_[i] = v;
            continue;
        }
        const scalar m = s.mass(i);
        const scalar im = fluidInverseMass(i, held);
        const scalar Wdg = W[i]/depth*dt*gamma_[i];
        // v**_0: v** without its (implicit) pressure-gradient part
        vss_[i] = v + im*(m*dt*g + contactImpulse[i]);
        gammaStar_[i] = gamma_[i]/(1 + Wdg*im);
        vStar_[i] = (vss_[i] + Wdg*im*Ug_[i])/(1 + Wdg*im);
    }
}


void Foam::vansCloud::spreadDragFields(const scalar dt)
{
    const nscd::System& s = grains_.system();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const scalar rhoK = fluid_->rhoK();

    // Drag fields: K = sum (V_pc/V_c) gamma*/rho, K v**, and for model B
    // the solid part of the pressure force phi grad(p)
    scalarField& K = Kdrag_.primitiveFieldRef();
    vectorField& KU = KUs_.primitiveFieldRef();
    vectorField& sp = solidPressureForce_.primitiveFieldRef();
    scalarField& D = Ds_.primitiveFieldRef();
    scalarField& Kp = Kp_.primitiveFieldRef();
    scalarField& B = resolved_.Bs().primitiveFieldRef();
    scalarField& Kg = resolved_.Kg().primitiveFieldRef();
    scalarField& Br = resolved_.Br().primitiveFieldRef();
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
    const UList<scalar> held(scalars(columns::heldFraction));
    const UList<vector> defect(vectors(columns::dragImpulseDefect));
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        const label c = ec[e];
        K[c] += ev[e]*gammaStar_[gi]/rhoK;
        if (settings_.rotation)
        {
            // rigid-body velocity of the grain at the cell (resolved
            // regime: Brinkman penalisation of translation and rotation)
            KU[c] +=
                ev[e]*gammaStar_[gi]/rhoK
               *(vss_[gi] + (omega_[gi] ^ leverArm(e)));
        }
        else
        {
            KU[c] += ev[e]*gammaStar_[gi]/rhoK*vss_[gi];
        }
        sp[c] += ev[e]*gradpg_[gi];
        if (!s.fixed(gi))
        {
            const scalar im = fluidInverseMass(gi, held);
            const scalar Wi = W[gi]/depth;
            // the drag impulse the grain received beyond what the fluid gave
            // last step, taken from the fluid now (its share V_pc/W_p)
            KU[c] -= ev[e]*defect[gi]/(Wi*dt*rhoK);
            D[c] += ev[e]*Wi*dt*rhoK*im/(1 + Wi*dt*gamma_[gi]*im);
            Kp[c] += ev[e]*gammaStar_[gi]*Wi*dt*im;
            if (resolved_[gi])
            {
                // (never held: im = 1/m)
                B[c] += ev[e]*Wi*dt*gamma_[gi]*im/(1 + Wi*dt*gamma_[gi]*im);
                Kg[c] += ev[e]*gammaStar_[gi]*dt/rhoK;
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
    resolved_.Br().correctBoundaryConditions();
    resolved_.Bs().correctBoundaryConditions();
    resolved_.Kg().correctBoundaryConditions();
    Ds_.correctBoundaryConditions();
    Kp_.correctBoundaryConditions();
    Kdrag_.correctBoundaryConditions();
    KUs_.correctBoundaryConditions();
    solidPressureForce_.correctBoundaryConditions();
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vansCloud::mapGrains()
{
    const scalar n = settings_.grainPorosity;
    if (n > 0)
    {
        // porous grains (thesis 4.3.2): the fluid sees the concentric
        // disc/sphere of the solid volume (1 - n) V_p
        const nscd::System& s = grains_.system();
        const scalar k = adapter_.twoD() ? std::sqrt(1 - n) : std::cbrt(1 - n);
        const std::size_t nGrains = s.size();
        std::vector<overlapMapping::Vec3> c(nGrains);
        std::vector<double> r(nGrains);
        for (std::size_t i = 0; i < nGrains; ++i)
        {
            const nscd::Vec3& x = s.positions()[i];
            c[i] = overlapMapping::Vec3(x.x(), x.y(), x.z());
            r[i] = k*s.radii()[i];
        }
        adapter_.map(c.data(), r.data(), label(nGrains));
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
    fluid_->gather(adapter_, grains_.system().size(), rhog_, nug_);
    predictGrains(U, fvc::grad(p)(), dt);
    if (settings_.rotation)
    {
        gatherAngularVelocities();
    }
    spreadDragFields(dt);
    // pf + K_p, pf = eps (model A) or 1 (model B)
    if (modelA())
    {
        pressureCoefficient_ = voidFraction_ + Kp_;
    }
    else
    {
        pressureCoefficient_ = dimensionedScalar("one", dimless, 1.0) + Kp_;
    }
}


void Foam::vansCloud::predictHeat(const scalar dt)
{
    heat_.predict(dt, voidFraction_, scalars(columns::grainReynolds));
}


void Foam::vansCloud::setHeatSources(const volScalarField& T, const scalar dt)
{
    // heat into the grains from the coupling sources (e.g. an immersed
    // droplet's Leidenfrost film, nscd units: W/m in 2D; empty: none); not
    // part of the fluid-grain exchange
    List<scalar> sourceHeat;
    for (const grainCouplingSource* s : couplingSources_)
    {
        s->addGrainHeat(sourceHeat);
    }
    heat_.setSources(T, dt, sourceHeat);
}


Foam::scalar Foam::vansCloud::maxGrainReynolds() const
{
    scalar m = 0;
    const UList<scalar> ReP(scalars(columns::grainReynolds));
    forAll(ReP, i)
    {
        if (grains_.owned(i))
        {
            m = max(m, ReP[i]);
        }
    }
    return grains_.decomposed() ? returnReduce(m, maxOp<scalar>()) : m;
}


Foam::scalar Foam::vansCloud::meanGrainReynolds() const
{
    scalar s = 0;
    const UList<scalar> ReP(scalars(columns::grainReynolds));
    forAll(ReP, i)
    {
        if (grains_.owned(i))
        {
            s += ReP[i];
        }
    }
    const label n = grains_.nGrainsTotal();
    return
        (grains_.decomposed() ? returnReduce(s, sumOp<scalar>()) : s)
       /max(n, label(1));
}


// ************************************************************************* //
