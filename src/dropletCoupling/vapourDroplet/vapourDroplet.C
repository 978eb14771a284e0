// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet (see vapourDroplet.H)

Description
    Construction, the droplet radius (eq. 4.15), the per-step mapping onto
    the cells (occupancy chi_c, ring weights, V_p of the absorbed grains,
    penalisation rate K) and the end of the fluid step (motion, hand-over
    to the capillary barrier).  Settings, restart and output, heat and
    vapour, grain momentum exchange and the barrier are in
    vapourDropletSettings.C, vapourDropletIO.C, vapourDropletHeat.C,
    vapourDropletGrainMomentum.C and vapourDropletBarrier.C.
\*---------------------------------------------------------------------------*/

#include "vapourDroplet.H"
#include "uniformDimensionedFields.H"
#include "Switch.H"
#include "meshTools.H"
#include "vansCloud.H"
#include "foamTools.H"
#include "mathematicalConstants.H"

#include <algorithm>
#include <cmath>

using Foam::constant::mathematical::pi;

// * * * * * * * * * * * * * Static Member Functions * * * * * * * * * * * * //

double Foam::vapourDroplet::lensOverlap
(
    const double R,
    const double r,
    const double d,
    const bool twoD
)
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
        const double a1 =
            std::acos(std::clamp((d*d + r*r - R*R)/(2*d*r), -1.0, 1.0));
        const double a2 =
            std::acos(std::clamp((d*d + R*R - r*r)/(2*d*R), -1.0, 1.0));
        const double k = (-d + r + R)*(d + r - R)*(d - r + R)*(d + r + R);
        return r*r*a1 + R*R*a2 - 0.5*std::sqrt(std::max(k, 0.0));
    }
    const double h = R + r - d;
    return pi*h*h*(d*d + 2*d*r - 3*r*r + 2*d*R + 6*r*R - 3*R*R)/(12*d);
}

const Foam::word Foam::vapourDroplet::historyColumns[4] =
{
    "dropletPrevVelocity", "dropletPrevForce", "dropletPrevVelocity2",
    "dropletGasForceChange"
};


const Foam::word Foam::vapourDroplet::grainVapourColumn("dropletVapourHeat");


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
    grainDrag_(true), muL_(2.82e-4), sigma_(0), localRelease_(false),
    grainRelease_(false),
    carryGrains_(false),
    film_(false), muV_(0), kappaF_(0), kL_(-1), porosity_(0), drag_(nullptr),
    rhoF_(0), CpF_(0), diffusivity_(0),
    x_(Zero), u_(Zero), m_(0), y0_(0), mdot_(0), Qf_(0), Qp_(0), Ff_(Zero),
    Vdot_(0), pendingVapour_(0), Vp_(0), Fp_(Zero), Fw_(Zero),
    walls_(mesh.bounds()), wallActive_(false),
    wallClamped_(false), S_(Zero), nGrainsIn_(0), Mp_(0), Fc_(Zero),
    barrierId_(-1), barrierActive_(false),
    grainForce_(),
    prevDt_(0),
    adapter_(mesh),
    chi_(mesh.nCells(), Zero),
    ring_(mesh.nCells(), Zero),
    sinkDirection_(),
    sinkHeat_(),
    filmGrain_(),
    filmHeat_(),
    Qfilm_(0),
    liquidHeat_(),
    releaseWeight_(mesh.nCells(), Zero),
    K_(0),
    timeIndex_(-1),
    cloud_(nullptr),
    restart_(mesh, *this)
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
    if (m_ > 0 && cloud_)
    {
        const nscd::System& sys = cloud_->grains().system();
        const scalar Rprev = radius();
        const bool twoD = adapter_.twoD();
        const auto& pos = sys.positions();
        const auto& rad = sys.radii();
        // over every grain once: the owned ones, summed over the ranks
        // when the grains are decomposed
        const grainCloud& grains = cloud_->grains();
        scalar Vp = 0;
        for (std::size_t g = 0; g < rad.size(); ++g)
        {
            if (!grains.owned(label(g)))
            {
                continue;
            }
            const double dx = pos[g][0] - x_.x();
            const double dy = pos[g][1] - x_.y();
            const double dz = twoD ? 0.0 : pos[g][2] - x_.z();
            Vp += lensOverlap
            (
                Rprev, rad[g], std::sqrt(dx*dx + dy*dy + dz*dz), twoD
            );
        }
        if (grains.decomposed())
        {
            reduce(Vp, sumOp<scalar>());
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
    if (grainRelease_)
    {
        grainReleaseWeights();
    }
    else
    {
        releaseWeights(h);
    }
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


void Foam::vapourDroplet::endStep()
{
    const Time& runTime = mesh_.time();
    const scalar dt = runTime.deltaTValue();

    // gravity of the coupled grains (constant/g, read by grainCloud)
    vector g(Zero);
    if (cloud_)
    {
        g = foamTools::toVector(cloud_->grains().system().gravity());
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
        moveWithGrains(dt, g, u);
    }

    // capillary entry barrier: the droplet moves inside the NSCD step of
    // the grains (vapourDroplet.H); the step is finished by
    // afterGrainStep(), which vansCloud::evolve calls through
    // fv::vapourDropletSource (grainCouplingSource)
    nscd::System* sysPtr = barrierSystem();
    if (sysPtr)
    {
        handToBarrier(*sysPtr, dt, move, u);
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


void Foam::vapourDroplet::moveWithGrains
(
    const scalar dt,
    const vector& g,
    vector& u
)
{
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


// ************************************************************************* //
