/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet (see vapourDroplet.H)
\*---------------------------------------------------------------------------*/

#include "vapourDroplet.H"
#include "grainDictionaryTools.H"
#include "uniformDimensionedFields.H"
#include "Switch.H"
#include "meshTools.H"
#include "grainCloud.H"
#include "mathematicalConstants.H"

#include <algorithm>
#include <cmath>
#include <sstream>

using Foam::constant::mathematical::pi;

// * * * * * * * * * * * * * * * * Local helpers * * * * * * * * * * * * * * //

namespace
{

Foam::scalar requirePositive
(
    const Foam::dictionary& d,
    const Foam::word& key,
    const char* meaning
)
{
    using namespace Foam;
    if (!d.found(key))
    {
        FatalIOErrorInFunction(d)
            << "Missing keyword '" << key << "' in " << d.name()
            << ": " << meaning << " (thesis eq. 4.15-4.17)." << nl
            << "    Fix: add '" << key << " <value>;'."
            << exit(FatalIOError);
    }
    return grainTools::getPositive(d, key);
}

//- Overlap of a droplet of radius R with a grain of radius r at centre
//  distance d: 2D the lens area of two discs [m^2], 3D the lens volume of
//  two spheres [m^3] (exact, elementary geometry)
double lensOverlap(double R, double r, double d, bool twoD)
{
    if (d >= R + r)
    {
        return 0;
    }
    if (d <= std::abs(R - r))
    {
        const double m = std::min(R, r);
        return twoD ? pi*m*m : 4.0/3.0*pi*m*m*m;
    }
    if (twoD)
    {
        const double a1 = std::acos(std::clamp((d*d + r*r - R*R)/(2*d*r), -1.0, 1.0));
        const double a2 = std::acos(std::clamp((d*d + R*R - r*r)/(2*d*R), -1.0, 1.0));
        const double k = (-d + r + R)*(d + r - R)*(d - r + R)*(d + r + R);
        return r*r*a1 + R*R*a2 - 0.5*std::sqrt(std::max(k, 0.0));
    }
    const double h = R + r - d;
    return pi*h*h*(d*d + 2*d*r - 3*r*r + 2*d*R + 6*r*R - 3*R*R)/(12*d);
}

//- Two lists of the restart dictionary d that go together (one entry per
//  grain or cell): FatalIOError naming both if their sizes differ
template<class TypeA, class TypeB>
void readListPair
(
    const Foam::dictionary& d,
    const Foam::word& nameA,
    const Foam::word& nameB,
    Foam::List<TypeA>& a,
    Foam::List<TypeB>& b
)
{
    a = d.get<Foam::List<TypeA>>(nameA);
    b = d.get<Foam::List<TypeB>>(nameB);
    if (a.size() != b.size())
    {
        FatalIOErrorInFunction(d)
            << nameA << " (" << a.size() << ") and " << nameB << " ("
            << b.size() << ") differ in size in " << d.name() << Foam::nl
            << "    Fix: restart from an unedited write time, or delete both"
            << " entries." << Foam::exit(Foam::FatalIOError);
    }
}

} // End anonymous namespace


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vapourDroplet::readDict()
{
    const wordList allowed
    {
        "centre", "radius", "diameter", "velocity", "liquidDensity",
        "latentHeat", "vapourisationTemperature", "vapourDensity", "moving",
        "blowing", "penalisationFactor", "grainDrag", "liquidViscosity",
        "surfaceTension", "vapourRelease", "filmConduction", "vapourViscosity"
    };
    grainTools::checkKeywords(dict_, allowed);

    if (!dict_.found("centre"))
    {
        FatalIOErrorInFunction(dict_)
            << "Missing keyword 'centre' in " << dict_.name()
            << ": the droplet centre x_d [m]." << nl
            << "    Fix: add e.g. 'centre (0.005 0.0225 0.0005);'."
            << exit(FatalIOError);
    }
    x_ = dict_.get<vector>("centre");
    u_ = dict_.getOrDefault<vector>("velocity", Zero);

    const bool hasR = dict_.found("radius");
    const bool hasD = dict_.found("diameter");
    if (hasR == hasD)
    {
        FatalIOErrorInFunction(dict_)
            << (hasR ? "Both keywords 'radius' and 'diameter'" : "Neither"
                " keyword 'radius' nor 'diameter'")
            << " in " << dict_.name() << ": the droplet size is given by"
            << " exactly one of them [m]." << nl
            << "    Fix: keep one, e.g. 'diameter 2.5e-3;'."
            << exit(FatalIOError);
    }
    const scalar R0 =
        hasR
      ? grainTools::getPositive(dict_, "radius")
      : 0.5*grainTools::getPositive(dict_, "diameter");

    rhoL_ = requirePositive(dict_, "liquidDensity", "liquid density rho_l [kg/m^3]");
    L_ = requirePositive(dict_, "latentHeat", "latent heat of vaporisation L [J/kg]");
    Td_ = requirePositive
    (
        dict_, "vapourisationTemperature", "vaporisation temperature T_d [K]"
    );
    moving_ = dict_.getOrDefault<Switch>("moving", false);
    blowing_ = dict_.getOrDefault<Switch>("blowing", true);
    penalisationFactor_ =
        grainTools::getPositiveOrDefault(dict_, "penalisationFactor", 100);
    grainDrag_ = dict_.getOrDefault<Switch>("grainDrag", true);
    // water at 100 C: 281.8e-6 Pa s (IAPWS 2008 viscosity formulation,
    // Huber et al., J. Phys. Chem. Ref. Data 38 (2009) 101, saturated liquid)
    muL_ = grainTools::getPositiveOrDefault(dict_, "liquidViscosity", 2.82e-4);
    // capillary entry barrier (vapourDroplet.H, "Capillary entry barrier")
    sigma_ = dict_.getOrDefault<scalar>("surfaceTension", 0);
    if (!(sigma_ >= 0) || !std::isfinite(sigma_))
    {
        FatalIOErrorInFunction(dict_)
            << "surfaceTension " << sigma_ << " in " << dict_.name()
            << " must be >= 0 [N/m]." << nl
            << "    Fix: e.g. 'surfaceTension 0.0589;' (water at 100 C) or"
            << " 0 (no capillary barrier)." << exit(FatalIOError);
    }

    // where the vapour leaves the surface (vapourDroplet.H, "Blowing")
    {
        const word release = dict_.getOrDefault<word>("vapourRelease", "uniform");
        if (release != "uniform" && release != "heatFlux")
        {
            FatalIOErrorInFunction(dict_)
                << "vapourRelease " << release << " in " << dict_.name()
                << " is not a release mode." << nl
                << "    Fix: 'vapourRelease uniform;' (uniform blowing over"
                << " the surface, thesis 4.3.2, the default) or"
                << " 'vapourRelease heatFlux;' (vapour leaves where the heat"
                << " entered)." << exit(FatalIOError);
        }
        localRelease_ = (release == "heatFlux");
    }

    // Leidenfrost film conduction (vapourDroplet.H)
    film_ = dict_.getOrDefault<Switch>("filmConduction", false);
    // water vapour at 100 C, 0.1 MPa: 12.27e-6 Pa s (IAPWS 2008 viscosity
    // formulation, Huber et al., J. Phys. Chem. Ref. Data 38 (2009) 101)
    muV_ = grainTools::getPositiveOrDefault(dict_, "vapourViscosity", 1.227e-5);
    if (film_ && !(sigma_ > 0))
    {
        FatalIOErrorInFunction(dict_)
            << "filmConduction yes in " << dict_.name() << " needs the"
            << " capillary entry barrier: the film's load is the grain's"
            << " contact force on the droplet surface." << nl
            << "    Fix: set surfaceTension (e.g. 0.05891, water at 100 C) or"
            << " filmConduction no." << exit(FatalIOError);
    }
    if (film_ && !adapter_.twoD())
    {
        FatalIOErrorInFunction(dict_)
            << "filmConduction yes in " << dict_.name() << ": the film model"
            << " is derived for discs (2D, one-cell-thick mesh) only." << nl
            << "    Fix: filmConduction no for a 3D mesh." << exit(FatalIOError);
    }

    // drag law and grain porosity of couplingProperties (grains present)
    {
        IOobject io
        (
            "couplingProperties", mesh_.time().constant(), mesh_,
            IOobject::MUST_READ, IOobject::NO_WRITE, false
        );
        if (io.typeHeaderOk<IOdictionary>(true))
        {
            const IOdictionary cp(io);
            porosity_ = cp.getOrDefault<scalar>("grainPorosity", 0);
            if (grainDrag_ && cp.found("dragModel"))
            {
                drag_ = dragModel::New(cp);
            }
        }
    }

    // fluid properties
    const IOdictionary transport
    (
        IOobject
        (
            "transportProperties", mesh_.time().constant(), mesh_,
            IOobject::MUST_READ, IOobject::NO_WRITE, false
        )
    );
    for (const word key : {"rho", "Cp", "kappa", "nu"})
    {
        if (!transport.found(key))
        {
            FatalIOErrorInFunction(transport)
                << "Keyword '" << key << "' missing in " << transport.name()
                << ": the droplet (" << dict_.name() << ") needs the fluid"
                << " density, heat capacity and conductivity (heat transfer"
                << " on) and viscosity." << nl
                << "    Fix: add rho, nu, Cp, kappa to " << transport.name()
                << " and heatTransferModel to couplingProperties."
                << exit(FatalIOError);
        }
    }
    rhoF_ = transport.get<scalar>("rho");
    CpF_ = transport.get<scalar>("Cp");
    kappaF_ = transport.get<scalar>("kappa");
    const scalar alpha = transport.get<scalar>("kappa")/(rhoF_*CpF_);
    diffusivity_ = max(alpha, transport.get<scalar>("nu"));
    scalar rhoVtransport = -1;
    if (transport.isDict("vapour"))
    {
        const dictionary& vd = transport.subDict("vapour");
        rhoVtransport = vd.getOrDefault<scalar>("rho", -1);
        diffusivity_ = max(diffusivity_, vd.getOrDefault<scalar>("D", 0));
    }
    if (dict_.found("vapourDensity"))
    {
        rhoV_ = grainTools::getPositive(dict_, "vapourDensity");
    }
    else if (rhoVtransport > 0)
    {
        rhoV_ = rhoVtransport;
    }
    else
    {
        FatalIOErrorInFunction(dict_)
            << "No vapour density: keyword 'vapourDensity' missing in "
            << dict_.name() << " and no vapour { rho ...; } in "
            << transport.name() << "." << nl
            << "    Fix: add 'vapourDensity <rho_v kg/m^3>;' (e.g. 0.6)."
            << exit(FatalIOError);
    }

    // liquid mass from the radius (eq. 4.15 with V_p = 0)
    const scalar V =
        adapter_.twoD()
      ? pi*R0*R0*adapter_.depth()
      : 4.0/3.0*pi*R0*R0*R0;
    m_ = rhoL_*V;
    y0_ = x_.y();
}


void Foam::vapourDroplet::readRestart()
{
    IOobject io
    (
        "droplet", mesh_.time().timeName(), "uniform", mesh_,
        IOobject::MUST_READ, IOobject::NO_WRITE, false
    );
    if (!io.typeHeaderOk<IOdictionary>(true))
    {
        return;
    }
    const IOdictionary d(io);
    x_ = d.get<vector>("centre");
    u_ = d.get<vector>("velocity");
    m_ = d.get<scalar>("mass");
    y0_ = d.get<scalar>("y0");
    mdot_ = d.get<scalar>("mdot");
    pendingVapour_ = d.get<scalar>("pendingVapour");
    Vp_ = d.get<scalar>("grainVolume");
    if (d.found("grainHistory"))
    {
        restartHistory_ = d.subDict("grainHistory");
    }
    if (film_ && d.found("filmHeat"))
    {
        readListPair(d, "filmGrain", "filmHeat", filmGrain_, filmHeat_);
    }
    if (localRelease_ && d.found("sinkHeat"))
    {
        readListPair(d, "sinkDirection", "sinkHeat", sinkDirection_, sinkHeat_);
    }
    Info<< "vapourDroplet: restart from " << d.objectPath() << endl;
}


void Foam::vapourDroplet::restoreGrainHistory(const nscd::System& sys)
{
    const dictionary h(restartHistory_);
    restartHistory_.clear();
    const label n = sys.size();
    const labelList grains(h.get<labelList>("grains"));
    const List<vector> v1(h.get<List<vector>>("velocity"));
    const List<vector> F1(h.get<List<vector>>("force"));
    const bool second = h.found("velocity2");
    const List<vector> v2(second ? h.get<List<vector>>("velocity2") : v1);
    const List<vector> dG
    (
        second ? h.get<List<vector>>("gasForceChange") : List<vector>(v1.size(), Zero)
    );
    if
    (
        v1.size() != grains.size() || F1.size() != grains.size()
     || v2.size() != grains.size() || dG.size() != grains.size()
     || (grains.size() && (min(grains) < 0 || max(grains) >= n))
    )
    {
        FatalIOErrorInFunction(h)
            << "grainHistory of the droplet restart file does not match the "
            << n << " grains of the restarted case (list sizes or grain"
            << " labels)." << nl
            << "    Fix: restart from a time written by the same case, or"
            << " delete grainHistory from <time>/uniform/droplet (the first"
            << " step then runs without the contact predictor)."
            << exit(FatalIOError);
    }
    const auto& vel = sys.velocities();
    const bool twoD = adapter_.twoD();
    prevVelocity_.setSize(n);
    forAll(prevVelocity_, g)
    {
        prevVelocity_[g] =
            vector(vel[g][0], vel[g][1], twoD ? 0.0 : vel[g][2]);
    }
    prevVelocity2_ = prevVelocity_;
    prevForce_ = List<vector>(n, Zero);
    gasForceChange_ = List<vector>(n, Zero);
    forAll(grains, j)
    {
        prevVelocity_[grains[j]] = v1[j];
        prevVelocity2_[grains[j]] = v2[j];
        prevForce_[grains[j]] = F1[j];
        gasForceChange_[grains[j]] = dG[j];
    }
    if (!second)
    {
        prevVelocity2_.clear();
        gasForceChange_.clear();
    }
    prevDt_ = h.get<scalar>("dt");
}


void Foam::vapourDroplet::writeRestart() const
{
    IOdictionary d
    (
        IOobject
        (
            "droplet", mesh_.time().timeName(), "uniform", mesh_,
            IOobject::NO_READ, IOobject::NO_WRITE, false
        )
    );
    d.add("centre", x_);
    d.add("velocity", u_);
    d.add("mass", m_);
    d.add("y0", y0_);
    d.add("mdot", mdot_);
    d.add("pendingVapour", pendingVapour_);
    d.add("grainVolume", Vp_);
    if (film_)
    {
        d.add("filmGrain", filmGrain_);
        d.add("filmHeat", filmHeat_);
    }
    if (localRelease_)
    {
        d.add("sinkDirection", sinkDirection_);
        d.add("sinkHeat", sinkHeat_);
    }
    // predictor history of the grains near the droplet (vapourDroplet.H,
    // "Gas drag of the grains inside", Restart)
    const label n = prevVelocity_.size();
    if
    (
        n > 0 && prevForce_.size() == n && prevDt_ > 0
     && mesh_.foundObject<grainCloudReference>(grainCloud::registryName)
    )
    {
        const nscd::System& sys =
            mesh_.lookupObject<grainCloudReference>(grainCloud::registryName)
            .cloud().system();
        const bool second =
            prevVelocity2_.size() == n && gasForceChange_.size() == n;
        const bool twoD = adapter_.twoD();
        const scalar R = radius();
        DynamicList<label> grains;
        if (label(sys.size()) == n)
        {
            const auto& pos = sys.positions();
            const auto& rad = sys.radii();
            for (label g = 0; g < n; ++g)
            {
                const scalar dx = pos[g][0] - x_.x();
                const scalar dy = pos[g][1] - x_.y();
                const scalar dz = twoD ? 0.0 : pos[g][2] - x_.z();
                if (sqrt(dx*dx + dy*dy + dz*dz) < 2*R + rad[g])
                {
                    grains.append(g);
                }
            }
        }
        dictionary h;
        h.add("dt", prevDt_);
        h.add("grains", labelList(grains));
        h.add("velocity", List<vector>(UIndirectList<vector>(prevVelocity_, grains)));
        h.add("force", List<vector>(UIndirectList<vector>(prevForce_, grains)));
        if (second)
        {
            h.add
            (
                "velocity2",
                List<vector>(UIndirectList<vector>(prevVelocity2_, grains))
            );
            h.add
            (
                "gasForceChange",
                List<vector>(UIndirectList<vector>(gasForceChange_, grains))
            );
        }
        d.add("grainHistory", h);
    }
    d.regIOobject::write();
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::vapourDroplet::vapourDroplet(const fvMesh& mesh)
:
    mesh_(mesh),
    dict_
    (
        IOobject
        (
            "dropletProperties", mesh.time().constant(), mesh,
            IOobject::MUST_READ, IOobject::NO_WRITE, false
        )
    ),
    rhoL_(0), L_(0), Td_(0), rhoV_(0), moving_(false), blowing_(true),
    penalisationFactor_(100),
    grainDrag_(true), muL_(2.82e-4), sigma_(0), localRelease_(false), film_(false), muV_(0), kappaF_(0), porosity_(0), drag_(nullptr),
    rhoF_(0), CpF_(0), diffusivity_(0),
    x_(Zero), u_(Zero), m_(0), y0_(0), mdot_(0), Qf_(0), Qp_(0), Ff_(Zero),
    Vdot_(0), pendingVapour_(0), Vp_(0), Fp_(Zero), Fw_(Zero),
    walls_(mesh.bounds()), wallActive_(false),
    wallClamped_(false), S_(Zero), nGrainsIn_(0), Mp_(0), Fc_(Zero),
    barrierId_(-1), barrierActive_(false),
    grainForce_
    (
        IOobject
        (
            "dropletGrainForce", mesh.time().timeName(), mesh,
            IOobject::NO_READ, IOobject::NO_WRITE, true
        ),
        label(0)
    ),
    prevVelocity_(),
    prevForce_(),
    prevDt_(0),
    prevVelocity2_(),
    gasForceChange_(),
    adapter_(mesh),
    chi_(mesh.nCells(), Zero),
    ring_(mesh.nCells(), Zero),
    sinkDirection_(),
    sinkHeat_(),
    filmGrain_(),
    filmHeat_(),
    Qfilm_(0),
    grainHeat_
    (
        IOobject
        (
            "dropletGrainHeat", mesh.time().timeName(), mesh,
            IOobject::NO_READ, IOobject::NO_WRITE, true
        ),
        label(0)
    ),
    releaseWeight_(mesh.nCells(), Zero),
    K_(0),
    timeIndex_(-1)
{
    readDict();
    readRestart();

    Info<< "vapourDroplet: centre " << x_ << " m, radius " << radius()
        << " m, mass " << m_ << " kg" << (adapter_.twoD() ? " (over the mesh"
        " depth)" : "") << ", rho_l " << rhoL_ << ", L " << L_ << " J/kg, T_d "
        << Td_ << " K, rho_v " << rhoV_ << " kg/m^3, moving "
        << Switch(moving_) << ", blowing " << Switch(blowing_) << endl;
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::scalar Foam::vapourDroplet::radius() const
{
    const scalar V = volume() + Vp_;
    return
        adapter_.twoD()
      ? std::sqrt(V/(pi*adapter_.depth()))
      : std::cbrt(3*V/(4*pi));
}


void Foam::vapourDroplet::update()
{
    const Time& runTime = mesh_.time();
    if (timeIndex_ == runTime.timeIndex())
    {
        return;
    }
    timeIndex_ = runTime.timeIndex();
    const scalar dt = runTime.deltaTValue();

    // size h of the cell holding the centre
    // (2D: the centre's z is ignored, looked up at mid-depth)
    const label celli = mesh_.findCell
    (
        point
        (
            x_.x(), x_.y(),
            adapter_.twoD() ? mesh_.bounds().centre().z() : x_.z()
        )
    );
    scalar h = -1;
    if (celli >= 0)
    {
        h = adapter_.twoD()
          ? std::sqrt(mesh_.V()[celli]/adapter_.depth())
          : std::cbrt(mesh_.V()[celli]);
    }
    reduce(h, maxOp<scalar>());
    if (h < 0)
    {
        FatalErrorInFunction
            << "The droplet centre " << x_ << " is outside the mesh (bounds "
            << mesh_.bounds() << ") at time " << runTime.timeName() << nl
            << "    Fix: put 'centre' of constant/dropletProperties inside"
            << " the domain." << exit(FatalError);
    }
    K_ = penalisationFactor_*(1/dt + diffusivity_/(h*h));

    // absorbed grains (eq. 4.15): V_p = sum of the grain/droplet overlaps
    // at the radius of the previous step (one fixed-point pass per step)
    if (m_ > 0 && mesh_.foundObject<grainCloudReference>(grainCloud::registryName))
    {
        const nscd::System& sys =
            mesh_.lookupObject<grainCloudReference>(grainCloud::registryName)
           .cloud().system();
        const scalar Rprev = radius();
        const bool twoD = adapter_.twoD();
        const auto& pos = sys.positions();
        const auto& rad = sys.radii();
        scalar Vp = 0;
        for (std::size_t g = 0; g < rad.size(); ++g)
        {
            const double dx = pos[g][0] - x_.x();
            const double dy = pos[g][1] - x_.y();
            const double dz = twoD ? 0.0 : pos[g][2] - x_.z();
            Vp += lensOverlap
            (
                Rprev, rad[g], std::sqrt(dx*dx + dy*dy + dz*dz), twoD
            );
        }
        Vp_ = twoD ? Vp*adapter_.depth() : Vp;
    }
    else
    {
        Vp_ = 0;
    }

    // exact overlaps of the droplet (R) and of the disc R + h (ring)
    const scalar R = radius();
    const overlapMapping::Vec3 c(x_.x(), x_.y(), x_.z());
    const overlapMapping::Vec3 centres[2] = {c, c};
    const double radii[2] = {R > 0 ? R : 0.5*h, R + h};
    adapter_.map(centres, radii, 2);
    chi_ = 0;
    ring_ = 0;
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    const auto& ev = adapter_.entryVolume();
    const scalarField& V = mesh_.V();
    for (std::size_t k = 0; k < eg.size(); ++k)
    {
        const label ci = ec[k];
        (eg[k] == 0 ? chi_ : ring_)[ci] += ev[k]/V[ci];
    }
    ring_ = max(ring_ - chi_, scalar(0));
    if (!(R > 0))
    {
        chi_ = 0;
    }
    chi_ = min(chi_, scalar(1));

    // vapour released by the heat of the previous step (mass conserving
    // whatever the change of time step)
    Vdot_ = blowing_ ? pendingVapour_/(rhoV_*dt) : 0;
    pendingVapour_ = 0;
    releaseWeights(h);
}


Foam::vector Foam::vapourDroplet::directionTo(const vector& p) const
{
    vector r = p - x_;
    if (adapter_.twoD())
    {
        r.z() = 0;
    }
    const scalar mr = mag(r);
    return mr > 1e-9*max(radius(), VSMALL) ? r/mr : vector(Zero);
}


void Foam::vapourDroplet::releaseWeights(const scalar h)
{
    releaseWeight_ = 0;
    if (!localRelease_ || !blowing_ || sinkHeat_.empty())
    {
        return;
    }
    const scalarField& V = mesh_.V();
    const scalar R = radius();
    const scalar alpha = min(0.5*pi, max(pi/16, 2*h/max(R, VSMALL)));
    const scalar cosAlpha = std::cos(alpha);

    // local ring cells and their directions from the centre
    DynamicList<label> cells;
    DynamicList<vector> dirs;
    forAll(ring_, ci)
    {
        if (ring_[ci] > 0)
        {
            cells.append(ci);
            dirs.append(directionTo(mesh_.C()[ci]));
        }
    }
    const label ns = sinkHeat_.size();
    auto inCone = [&](const label s, const label j)
    {
        const vector& n = sinkDirection_[s];
        return magSqr(n) == 0 || (n & dirs[j]) >= cosAlpha;
    };

    // A_c: ring volume in each sink cell's cone, over all ranks
    scalarList A(ns, Zero);
    for (label s = 0; s < ns; ++s)
    {
        forAll(cells, j)
        {
            if (inCone(s, j))
            {
                A[s] += ring_[cells[j]]*V[cells[j]];
            }
        }
    }
    Pstream::listCombineGather(A, plusEqOp<scalar>());
    Pstream::listCombineScatter(A);
    const scalar Wring = gSum(ring_*V);
    if (!(Wring > 0))
    {
        return;
    }

    for (label s = 0; s < ns; ++s)
    {
        const scalar heat = sinkHeat_[s];
        forAll(cells, j)
        {
            const label ci = cells[j];
            if (A[s] > 0)
            {
                if (inCone(s, j))
                {
                    releaseWeight_[ci] += heat*ring_[ci]*V[ci]/A[s];
                }
            }
            else
            {
                releaseWeight_[ci] += heat*ring_[ci]*V[ci]/Wring;
            }
        }
    }
}


void Foam::vapourDroplet::setHeatSink(const scalarField& sink)
{
    if (!localRelease_)
    {
        return;
    }
    DynamicList<vector> dirs;
    DynamicList<scalar> heat;
    forAll(sink, ci)
    {
        // cells that gave heat to the droplet (a cell slightly below T_d,
        // s_c < 0, releases nothing: the release weights stay >= 0)
        if (sink[ci] > 0)
        {
            dirs.append(directionTo(mesh_.C()[ci]));
            heat.append(sink[ci]*mesh_.V()[ci]);
        }
    }
    List<List<vector>> allDirs(Pstream::nProcs());
    List<List<scalar>> allHeat(Pstream::nProcs());
    allDirs[Pstream::myProcNo()] = dirs;
    allHeat[Pstream::myProcNo()] = heat;
    Pstream::gatherList(allDirs);
    Pstream::scatterList(allDirs);
    Pstream::gatherList(allHeat);
    Pstream::scatterList(allHeat);
    sinkDirection_ =
        ListListOps::combine<List<vector>>(allDirs, accessOp<List<vector>>());
    sinkHeat_ =
        ListListOps::combine<List<scalar>>(allHeat, accessOp<List<scalar>>());

    // the film heat enters at the grains (the same on every rank: the
    // grain system is replicated)
    if (film_ && filmGrain_.size())
    {
        const nscd::System& sys =
            mesh_.lookupObject<grainCloudReference>(grainCloud::registryName)
           .cloud().system();
        forAll(filmGrain_, k)
        {
            if (filmGrain_[k] >= label(sys.size()) || !(filmHeat_[k] > 0))
            {
                continue;
            }
            const auto& xg = sys.positions()[filmGrain_[k]];
            sinkDirection_.append(directionTo(vector(xg[0], xg[1], xg[2])));
            sinkHeat_.append(filmHeat_[k]);
        }
    }
}


Foam::scalar Foam::vapourDroplet::filmThickness
(
    const scalar r,
    const scalar F,
    const scalar dT,
    const scalar muV,
    const scalar k,
    const scalar rhoV,
    const scalar L
)
{
    // I = int_0^inf s atan(s)/(1 + s^2)^3 ds (vapourDroplet.H)
    constexpr scalar I = 0.147262;
    return std::pow
    (
        24*I*muV*k*dT*std::pow(2*r, 1.5)/(rhoV*L*F),
        0.4
    );
}


void Foam::vapourDroplet::computeFilmHeat
(
    const nscd::System& sys,
    const scalar dt
)
{
    filmGrain_.clear();
    filmHeat_.clear();
    if (!film_ || barrierId_ < 0 || !(m_ > 0))
    {
        return;
    }
    const scalar depth = adapter_.depth();
    const std::vector<double>& rn = sys.droplet(barrierId_).grainImpulse;
    const std::vector<double>& T = sys.temperatures();
    DynamicList<label> grains;
    DynamicList<scalar> heat;
    for (std::size_t i = 0; i < rn.size(); ++i)
    {
        const scalar F = rn[i]/dt;      // N/m (2D, nscd units)
        const scalar dT = T[i] - Td_;
        if (!(F > 0) || !(dT > 0))
        {
            continue;
        }
        const scalar c = sys.material(sys.materials()[i]).heatCapacity;
        const bool bath = sys.fixedTemperature(i);
        if (!(c > 0) && !bath)
        {
            continue;   // temperature not integrated: no heat to give
        }
        const scalar r = sys.radii()[i];
        const scalar delta = filmThickness(r, F, dT, muV_, kappaF_, rhoV_, L_);
        const scalar G = pi*kappaF_*std::sqrt(2*r/delta);     // W/(m K)
        const scalar C = sys.mass(i)*c;                        // J/(m K)
        const scalar Gstar = bath ? G : G*C/(C + dt*G);
        grains.append(label(i));
        heat.append(Gstar*dT*depth);                           // W
    }
    filmGrain_.transfer(grains);
    filmHeat_.transfer(heat);
}


Foam::tmp<Foam::scalarField>
Foam::vapourDroplet::volumeSource(const scalar Vdot) const
{
    auto tq = tmp<scalarField>::New(ring_.size(), Zero);
    if (localRelease_)
    {
        const scalar S = gSum(releaseWeight_);
        if (S > 0)
        {
            tq.ref() = Vdot*releaseWeight_/(S*mesh_.V());
            return tq;
        }
    }
    const scalar W = gSum(ring_*mesh_.V());
    if (W > 0)
    {
        tq.ref() = Vdot*ring_/W;
    }
    return tq;
}


void Foam::vapourDroplet::setHeat(const scalar Qf, const scalar Qp)
{
    const scalar dt = mesh_.time().deltaTValue();
    Qf_ = Qf;
    Qp_ = Qp;
    // Leidenfrost film heat of the grains pressed on the surface (last NSCD
    // step), taken from them over this step by vansCloud's heat sources
    Qfilm_ = 0;
    if (film_ && mesh_.foundObject<grainCloudReference>(grainCloud::registryName))
    {
        const label n =
            mesh_.lookupObject<grainCloudReference>(grainCloud::registryName)
           .cloud().system().size();
        const scalar depth = adapter_.depth();
        grainHeat_.setSize(n);
        grainHeat_ = Zero;
        forAll(filmGrain_, k)
        {
            if (filmGrain_[k] < n)
            {
                grainHeat_[filmGrain_[k]] -= filmHeat_[k]/depth;
                Qfilm_ += filmHeat_[k];
            }
        }
    }
    mdot_ = (Qf_ + Qp_ + Qfilm_)/L_;     // eq. 4.16
    scalar loss = mdot_*dt;
    if (loss > m_)
    {
        loss = m_;
    }
    m_ -= loss;
    pendingVapour_ += loss;
}


void Foam::vapourDroplet::exchangeGrainMomentum
(
    const scalar dt,
    const bool move,
    const vector& gVec,
    vector& u
)
{
    Fp_ = Zero;
    S_ = Zero;
    Fw_ = Zero;
    nGrainsIn_ = 0;
    const bool twoD = adapter_.twoD();
    // nscd works per unit depth in 2D; the droplet over the mesh depth
    const scalar depth = twoD ? adapter_.depth() : 1;
    const scalar R = radius();
    const scalar V = volume() + Vp_;
    const vector un = u_;

    const bool grains =
        grainDrag_ && drag_.valid() && m_ > 0
     && mesh_.foundObject<grainCloudReference>(grainCloud::registryName);

    // Per grain i (nscd units): the force of the droplet on the grain,
    //   F_i = k_i (u - u^n) + e_i + w_i S,
    // linear in the droplet velocity u = u_d^{n+1} and in the surface
    // force S (see vapourDroplet.H).  Droplet sums (droplet units, x depth
    // in 2D): C = sum k_i [kg/s], Bv = sum (k_i u^n - e_i) [N],
    // W = sum w_i [-] (~ 1 - eps_l), so that
    //   F_p = -depth sum F_i = -C u + Bv - W S.
    label n = 0;
    List<scalar> k;
    List<vector> e;
    List<scalar> w;
    List<bool> inside;
    // predicted change of vansCloud's gas force on each grain [N]
    List<vector> gasChange;
    scalar C = 0;
    scalar W = 0;
    vector Bv(Zero);
    const nscd::System* sysPtr = nullptr;
    if (!grains)
    {
        grainForce_.clear();
        prevVelocity_.clear();
        prevForce_.clear();
        prevVelocity2_.clear();
        gasForceChange_.clear();
    }
    else
    {
        const grainCloud& cloud =
            mesh_.lookupObject<grainCloudReference>(grainCloud::registryName)
            .cloud();
        sysPtr = &cloud.system();
        n = sysPtr->size();
        const nscd::System& sys = *sysPtr;
        // grains that left through outlet patches in the last grain step
        // (grainCloud outletPatches): the predictor history follows them
        cloud.compactRemoved(prevVelocity_);
        cloud.compactRemoved(prevForce_);
        cloud.compactRemoved(prevVelocity2_);
        cloud.compactRemoved(gasForceChange_);
        if (!restartHistory_.empty())
        {
            restoreGrainHistory(sys);
        }
        grainForce_.setSize(n);
        grainForce_ = Zero;
        k.setSize(n, Zero);
        e.setSize(n, Zero);
        w.setSize(n, Zero);
        inside.setSize(n, false);
        // liquid fraction of the droplet (liquid + absorbed grains, eq. 4.15)
        const scalar epsL = max(1 - (1 - porosity_)*Vp_/V, scalar(1e-3));
        const auto& pos = sys.positions();
        const auto& vel = sys.velocities();
        const auto& rad = sys.radii();
        const vector gGrain(sys.gravity()[0], sys.gravity()[1], sys.gravity()[2]);
        // other forces of the previous step (contacts, gas), eq. 3.46 p^n
        const bool history =
            prevVelocity_.size() == n && prevForce_.size() == n && prevDt_ > 0;
        const bool history2 =
            history && prevVelocity2_.size() == n && gasForceChange_.size() == n;
        gasChange.setSize(n, Zero);

        // relaxation factor b_i = W_i dt gamma*_i/m_i of the gas drag of
        // vansCloud (eq. 3.48-3.50), estimated per grain as the cell's
        // volume-weighted mean over the free grains in the cell (field Kp =
        // sum_p (V_pc/V_c) b_p over the solid fraction 1 - eps) at the cell
        // of the grain centre; 0 without a vansCloud (no field Kp) or for a
        // grain outside the mesh; max over the processors
        List<scalar> bGas(n, Zero);
        {
            const volScalarField* KpPtr =
                mesh_.findObject<volScalarField>("Kp");
            const volScalarField* epsPtr =
                mesh_.findObject<volScalarField>("voidFraction");
            if (history && KpPtr && epsPtr)
            {
                const scalar zc = mesh_.bounds().centre().z();
                for (label g = 0; g < n; ++g)
                {
                    const vector xg
                    (
                        pos[g][0], pos[g][1], twoD ? zc : pos[g][2]
                    );
                    vector dx = xg - x_;
                    if (twoD)
                    {
                        dx.z() = 0;
                    }
                    if (sys.fixed(g) || mag(dx) > R + rad[g])
                    {
                        continue;
                    }
                    const label c = mesh_.findCell(xg);
                    if (c >= 0)
                    {
                        const scalar phiS = 1 - (*epsPtr)[c];
                        bGas[g] =
                            phiS > SMALL
                          ? min(max((*KpPtr)[c]/phiS, scalar(0)), scalar(1))
                          : 0;
                    }
                }
                Pstream::listCombineGather(bGas, maxEqOp<scalar>());
                Pstream::listCombineScatter(bGas);
            }
        }

        for (label g = 0; g < n; ++g)
        {
            const double dx = pos[g][0] - x_.x();
            const double dy = pos[g][1] - x_.y();
            const double dz = twoD ? 0.0 : pos[g][2] - x_.z();
            const scalar r = rad[g];
            const scalar lens =
                lensOverlap(R, r, std::sqrt(dx*dx + dy*dy + dz*dz), twoD);
            if (!(lens > 0))
            {
                continue;
            }
            const scalar Vg = twoD ? pi*r*r : 4.0/3.0*pi*r*r*r;
            const scalar f = min(lens/Vg, scalar(1));
            const vector v(vel[g][0], vel[g][1], twoD ? 0.0 : vel[g][2]);
            const scalar d = 2*r;
            const scalar Re = rhoL_*mag(un - v)*d/muL_;
            const scalar gam = drag_->gamma(epsL, Re, d, muL_, rhoL_, twoD);
            // liquid-displacing volume a_i = f_i (1 - n) V_i (2D: per depth)
            const scalar a = f*(1 - porosity_)*Vg;
            const scalar ci = a*gam;
            if (sys.fixed(g))
            {
                // fixed grain (infinite mass): backward Euler drag
                // c_i (u - v_i) and the full pressure share a_i S/V
                k[g] = ci;
                e[g] = ci*(un - v);
                w[g] = a/V;
            }
            else
            {
                // exponential integration over dt of
                //   m dv/dt = c (u(t) - v) + F_c,
                // u(t) = u^n + (t/dt)(u - u^n) (the droplet's constant
                // acceleration over the step), F_c = m g + a S/V + P
                // constant: exact impulse over the step
                //   m (v^{n+1} - v^n)/dt = c' (u^n - v^n)
                //     + (1 - phi) m (u - u^n)/dt + phi F_c,
                // c' = phi c, phi = (1 - e^{-x})/x, x = c dt/m; NSCD
                // applies m g and the contacts itself, so the droplet's
                // force is the above minus m g + P
                const scalar mi = sys.mass(g);
                const scalar x = ci*dt/mi;
                const scalar phi = x > 1e-12 ? -std::expm1(-x)/x : 1.0;
                vector P(Zero);
                if (history)
                {
                    P = mi*(v - prevVelocity_[g])/prevDt_ - mi*gGrain
                      - prevForce_[g];
                    // change of vansCloud's gas force over the step
                    // (vapourDroplet.H, "Gas drag of the grains inside"):
                    //   G^n - G^{n-1} = b_i (G^{n-1} - G^{n-2}
                    //     - m_i (2 dv^n - dv^{n-1})/dt),  dv^n = v^n - v^{n-1}
                    const vector dvn = v - prevVelocity_[g];
                    const vector dvp =
                        history2
                      ? vector(prevVelocity_[g] - prevVelocity2_[g])
                      : vector(Zero);
                    const vector dGp =
                        history2 ? gasForceChange_[g] : vector(Zero);
                    gasChange[g] = bGas[g]*(dGp - mi*(2*dvn - dvp)/dt);
                    if (twoD)
                    {
                        gasChange[g].z() = 0;
                    }
                    P += gasChange[g];
                }
                k[g] = (1 - phi)*mi/dt;
                e[g] = phi*ci*(un - v) - (1 - phi)*(mi*gGrain + P);
                w[g] = phi*a/V;
            }
            if (twoD)
            {
                e[g].z() = 0;
            }
            C += depth*k[g];
            W += depth*w[g];
            Bv += depth*(k[g]*un - e[g]);
            inside[g] = true;
            ++nGrainsIn_;
        }
        // the liquid keeps a share 1 - W > 0 of S (round-off guard for a
        // droplet with almost no liquid left: cap W at 1 - 1e-3 by scaling
        // all w_i, which keeps F_p = -depth sum F_i exact)
        const scalar Wmax = 1 - 1e-3;
        if (W > Wmax)
        {
            const scalar s = Wmax/W;
            forAll(w, g)
            {
                w[g] *= s;
            }
            W = Wmax;
        }
    }
    const scalar beta = 1 - W;

    // Droplet velocity u^{n+1} and surface force S.  Liquid (eq. 4.17 with
    // F_f + F_w = S):  m (u - u^n)/dt = m g + S + F_p = m g + beta S - C u + Bv
    const scalar VfRhoF = rhoF_*volume();
    if (move)
    {
        // free: S = F_pen + rho_f V_f ((u - u^n)/dt - g) (Uhlmann), linear
        // in u: (M' + dt C) u = M' u^n + dt (M' g + beta F_pen + Bv),
        // M' = m - beta rho_f V_f >= m - rho_f V_f > 0
        const scalar Mp = m_ - beta*VfRhoF;
        Mp_ = Mp;
        u = (Mp*un + dt*(Mp*gVec + beta*Ff_ + Bv))/(Mp + dt*C);
        meshTools::constrainDirection(mesh_, mesh_.solutionD(), u);
        // wall contact: the clamped components of u are imposed, S there
        // follows from the liquid balance (it contains the wall reaction)
        wallClamped_ = false;
        wallContact(dt, u);
        for (direction k = 0; k < vector::nComponents; ++k)
        {
            const scalar acc = (u[k] - un[k])/dt;
            if (wallClamped_[k])
            {
                S_[k] = (m_*(acc - gVec[k]) + C*u[k] - Bv[k])/beta;
            }
            else
            {
                S_[k] = Ff_[k] + VfRhoF*(acc - gVec[k]);
            }
        }
    }
    else
    {
        // held: u = u^n, S (holder included) from the liquid balance with
        // du/dt = 0
        Mp_ = 0;
        u = un;
        S_ = (-m_*gVec + C*u - Bv)/beta;
    }
    meshTools::constrainDirection(mesh_, mesh_.solutionD(), S_);

    if (!grains)
    {
        return;
    }
    const nscd::System& sys = *sysPtr;
    const auto& vel = sys.velocities();

    // F_i = k_i (u^{n+1} - u^n) + e_i + w_i S, F_p = -depth sum F_i
    for (label g = 0; g < n; ++g)
    {
        if (inside[g])
        {
            vector F = k[g]*(u - un) + e[g] + w[g]*S_;
            if (twoD)
            {
                F.z() = 0;
            }
            grainForce_[g] = F;
            Fp_ -= depth*F;
        }
    }

    // history for the predictor P of the next step
    prevVelocity2_ = prevVelocity_;
    gasForceChange_.transfer(gasChange);
    prevVelocity_.setSize(n);
    for (label g = 0; g < n; ++g)
    {
        prevVelocity_[g] = vector(vel[g][0], vel[g][1], twoD ? 0.0 : vel[g][2]);
    }
    prevForce_ = grainForce_;
    prevDt_ = dt;
}


bool Foam::vapourDroplet::wallContact(const scalar dt, vector& u)
{
    const scalar R = radius();
    const Vector<label>& sD = mesh_.solutionD();
    bool active = false;
    for (direction k = 0; k < vector::nComponents; ++k)
    {
        if (sD[k] < 0)
        {
            continue;       // empty direction (2D)
        }
        const scalar gLow = (x_[k] - R) - walls_.min()[k];
        const scalar gHigh = walls_.max()[k] - (x_[k] + R);
        if (u[k] < -gLow/dt)
        {
            u[k] = -gLow/dt;
            active = true;
            wallClamped_[k] = true;
        }
        else if (u[k] > gHigh/dt)
        {
            u[k] = gHigh/dt;
            active = true;
            wallClamped_[k] = true;
        }
    }
    wallActive_ = wallActive_ || active;
    return active;
}


void Foam::vapourDroplet::endStep()
{
    const Time& runTime = mesh_.time();
    const scalar dt = runTime.deltaTValue();

    // constant/g (vansFoam registers it on the Time registry)
    vector g(Zero);
    if (runTime.foundObject<uniformDimensionedVectorField>("g"))
    {
        g = runTime.lookupObject<uniformDimensionedVectorField>("g").value();
    }

    const bool move = moving_ && m_ > 0;
    Fc_ = Zero;
    vector u = u_;
    if (!move)
    {
        // droplet held (or gone): the grains still feel its liquid
        exchangeGrainMomentum(dt, false, g, u);
    }
    else
    {
        if (!runTime.foundObject<uniformDimensionedVectorField>("g"))
        {
            FatalErrorInFunction
                << "No gravity field g registered: the droplet motion (eq."
                << " 4.17) needs constant/g." << nl
                << "    Fix: add constant/g or set moving no."
                << exit(FatalError);
        }
        // eq. 4.17 with F_f the surface force of the fluid.  The
        // penalised fluid inside the droplet moves with it, so (Uhlmann
        // 2005, J. Comput. Phys. 209, eq. 13-14) the surface force is the
        // penalisation force plus the inside fluid's inertia and weight:
        //   F_f = F_pen + rho_f V_f (du_d/dt - g)
        // hence (m - rho_f V_f) du_d/dt = F_pen + F_p + F_w
        // + (m - rho_f V_f) g (buoyancy included; F_pen explicit, F_p
        // and F_w implicit: exchangeGrainMomentum)
        const scalar mEff = m_ - rhoF_*volume();
        if (!(mEff > 0))
        {
            FatalErrorInFunction
                << "Droplet lighter than the fluid it displaces (m = " << m_
                << " kg, rho_f V = " << rhoF_*volume() << " kg): the explicit"
                << " motion of eq. 4.17 is unstable." << nl
                << "    Fix: moving no in constant/dropletProperties."
                << exit(FatalError);
        }
        // u_d* = the velocity without F_p and F_w
        vector uStar = u_ + dt*(Ff_/mEff + g);
        meshTools::constrainDirection(mesh_, mesh_.solutionD(), uStar);
        wallActive_ = false;
        exchangeGrainMomentum(dt, true, g, u);
        // wall reaction where the contact was active: closes
        // (m - rho_f V_f)(u^{n+1} - u*) = dt (F_p + F_w) (= S - F_f)
        if (wallActive_)
        {
            const vector Fw(mEff*(u - uStar)/dt - Fp_);
            for (direction k = 0; k < vector::nComponents; ++k)
            {
                // only the wall-normal components the contact clamped
                Fw_[k] = (wallClamped_[k] ? Fw[k] : 0);
            }
        }
    }

    // capillary entry barrier: the droplet moves inside the NSCD step of
    // the grains (vapourDroplet.H); the step is finished by
    // afterGrainStep(), which grainCloud::evolve calls
    nscd::System* sysPtr = nullptr;
    if (sigma_ > 0 && mesh_.foundObject<grainCloudReference>(grainCloud::registryName))
    {
        grainCloud& cloud =
            mesh_.lookupObjectRef<grainCloudReference>(grainCloud::registryName)
           .cloud();
        sysPtr = &cloud.system();
        if (barrierId_ < 0)
        {
            nscd::System::Droplet d;
            d.radius = radius() > 0 ? radius() : 1;
            barrierId_ = sysPtr->addDroplet(d);
            cloud.setPostEvolve("vapourDroplet", [this]() { afterGrainStep(); });
            // grains inside the surface at the start are pushed out with up
            // to F_max each and kick the droplet: say so
            const bool twoD = adapter_.twoD();
            const auto& pos = sysPtr->positions();
            const auto& rad = sysPtr->radii();
            label nIn = 0;
            for (std::size_t gi = 0; gi < rad.size(); ++gi)
            {
                const scalar dx = pos[gi][0] - x_.x();
                const scalar dy = pos[gi][1] - x_.y();
                const scalar dz = twoD ? 0.0 : pos[gi][2] - x_.z();
                const scalar gap =
                    std::sqrt(dx*dx + dy*dy + dz*dz) - radius() - rad[gi];
                if (gap < -1e-3*rad[gi] && gap > -2*rad[gi])
                {
                    ++nIn;
                }
            }
            if (nIn > 0)
            {
                WarningInFunction
                    << nIn << " grains cross the droplet surface at time "
                    << runTime.timeName() << " (" << dict_.name()
                    << ": centre " << x_ << ", radius " << radius() << "):"
                    << " the capillary barrier (surfaceTension " << sigma_
                    << ") pushes each out with up to its entry force, which"
                    << " kicks the droplet." << nl
                    << "    Fix: start the droplet resting on the bed (no"
                    << " grain inside its surface)." << endl;
            }
        }
    }
    if (sysPtr)
    {
        const bool twoD = adapter_.twoD();
        const scalar depth = twoD ? adapter_.depth() : 1;
        nscd::System::Droplet& d = sysPtr->droplet(barrierId_);
        d.centre = nscd::Vec3(x_.x(), x_.y(), twoD ? 0.0 : x_.z());
        d.radius = radius() > 0 ? radius() : 1;
        d.impulse.setZero();
        std::fill(d.grainImpulse.begin(), d.grainImpulse.end(), 0.0);
        d.surfaceTension = m_ > 0 ? sigma_ : 0;
        if (move)
        {
            // the droplet's equation of exchangeGrainMomentum,
            // Mp (u - u^n) = dt F, with the capillary impulse added by NSCD
            const vector F(Mp_*(u - u_)/dt);
            d.mass = Mp_/depth;
            d.velocity = nscd::Vec3(u_.x(), u_.y(), twoD ? 0.0 : u_.z());
            d.force = nscd::Vec3(F.x(), F.y(), twoD ? 0.0 : F.z())/depth;
        }
        else
        {
            // held: a fixed surface
            d.mass = 0;
            d.velocity.setZero();
            d.force.setZero();
        }
        barrierActive_ = true;
        return;
    }

    if (move)
    {
        u_ = u;
        x_ += dt*u_;
    }
    finishStep();
}


void Foam::vapourDroplet::afterGrainStep()
{
    if (!barrierActive_)
    {
        return;
    }
    barrierActive_ = false;
    const scalar dt = mesh_.time().deltaTValue();
    const bool twoD = adapter_.twoD();
    const scalar depth = twoD ? adapter_.depth() : 1;
    const nscd::System& sys =
        mesh_.lookupObject<grainCloudReference>(grainCloud::registryName)
       .cloud().system();
    const nscd::System::Droplet& d = sys.droplet(barrierId_);
    computeFilmHeat(sys, dt);

    // capillary force on the droplet over the step [N] (2D: over the depth)
    Fc_ = vector(d.impulse.x(), d.impulse.y(), twoD ? 0.0 : d.impulse.z())*depth/dt;
    meshTools::constrainDirection(mesh_, mesh_.solutionD(), Fc_);

    if (moving_ && m_ > 0)
    {
        vector u(d.velocity.x(), d.velocity.y(), twoD ? 0.0 : d.velocity.z());
        meshTools::constrainDirection(mesh_, mesh_.solutionD(), u);
        const vector xNew(d.centre.x(), d.centre.y(), twoD ? x_.z() : d.centre.z());
        // the walls stay impenetrable: the capillary impulse may push the
        // droplet towards a wall (x_ is still x^n here)
        vector uc = u;
        const FixedList<bool, 3> clampedBefore = wallClamped_;
        wallClamped_ = false;
        if (wallContact(dt, uc))
        {
            for (direction k = 0; k < vector::nComponents; ++k)
            {
                if (wallClamped_[k])
                {
                    Fw_[k] += Mp_*(uc[k] - u[k])/dt;
                }
            }
            x_ += dt*uc;
        }
        else
        {
            x_ = xNew;
        }
        for (direction k = 0; k < vector::nComponents; ++k)
        {
            wallClamped_[k] = wallClamped_[k] || clampedBefore[k];
        }
        u_ = uc;
    }
    finishStep();
}


void Foam::vapourDroplet::finishStep()
{
    const Time& runTime = mesh_.time();
    if (Pstream::master())
    {
        if (!datPtr_.valid())
        {
            const fileName dir
            (
                runTime.globalPath()/"postProcessing"/"droplet"
               /runTime.timeName(runTime.startTime().value())
            );
            mkDir(dir);
            datPtr_.reset(new OFstream(dir/"droplet.dat"));
            datPtr_() << "# vapourDroplet (thesis eq. 4.15-4.17), SI units";
            if (adapter_.twoD())
            {
                datPtr_() << ", m/mdot/Q/Vdot over the mesh depth "
                    << adapter_.depth() << " m";
            }
            datPtr_() << nl
                << "# time x y u v m mdot Q_f Q_p R depth Vdot V_p"
                   " Fp_x Fp_y Fpen_x Fpen_y nGrainsIn Fw_x Fw_y S_x S_y"
                   " Fc_x Fc_y Q_film"
                << nl;
        }
        std::ostringstream os;
        os.precision(16);
        os  << runTime.value() << ' ' << x_.x() << ' ' << x_.y() << ' '
            << u_.x() << ' ' << u_.y() << ' ' << m_ << ' ' << mdot_ << ' '
            << Qf_ << ' ' << Qp_ << ' ' << radius() << ' ' << y0_ - x_.y()
            << ' ' << Vdot_ << ' ' << Vp_ << ' ' << Fp_.x() << ' '
            << Fp_.y() << ' ' << Ff_.x() << ' ' << Ff_.y() << ' '
            << nGrainsIn_ << ' ' << Fw_.x() << ' ' << Fw_.y() << ' '
            << S_.x() << ' ' << S_.y() << ' ' << Fc_.x() << ' ' << Fc_.y()
            << ' ' << Qfilm_;
        datPtr_() << os.str().c_str() << nl;
        datPtr_().flush();
    }

    if (runTime.writeTime())
    {
        writeRestart();
    }
}


// ************************************************************************* //
