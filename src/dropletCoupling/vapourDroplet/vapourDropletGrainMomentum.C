// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet grain momentum exchange (see vapourDroplet.H)

Description
    The droplet's force on the grains it overlaps and the grains' force on
    the droplet F_p (eq. 4.17, Newton's third law), implicit in the
    droplet's end-of-step velocity u and in the surface force S, in stages:
      1. grainForceCoefficients: per grain i the linear form
         F_i = k_i (u - u^n) + e_i + w_i S and the droplet sums C, Bv, W
         (exponential integration of a free grain with the other-force
         predictor P_i, backward Euler for a fixed grain);
      2. solveDropletVelocity: u and S from the droplet's equation (moving)
         or the liquid balance with du/dt = 0 (held), then the wall contact;
      3. applyGrainForces: F_i, F_p and the predictor's history.
    The equations and their sources are in vapourDroplet.H ("Liquid
    pressure on the grains", "Gas drag of the grains inside", "Walls").
\*---------------------------------------------------------------------------*/

#include "vapourDropletGrainMomentum.H"
#include "vansCloud.H"
#include "grainSums.H"
#include "meshTools.H"
#include "mathematicalConstants.H"

#include <cmath>

using Foam::constant::mathematical::pi;

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

Foam::List<Foam::scalar> Foam::vapourDroplet::gasRelaxationFactors
(
    const nscd::System& sys,
    const bool history
) const
{
    // relaxation factor b_i = W_i dt gamma*_i/m_i of the gas drag of
    // vansCloud (eq. 3.48-3.50), estimated per grain as the cell's
    // volume-weighted mean over the free grains in the cell (field Kp =
    // sum_p (V_pc/V_c) b_p over the solid fraction 1 - eps) at the cell
    // of the grain centre; 0 without a vansCloud (no field Kp) or for a
    // grain outside the mesh; max over the processors (decomposed grains:
    // the owner's value, the centre lying in its cells, copied to the
    // ghosts)
    const label n = sys.size();
    const bool twoD = adapter_.twoD();
    const scalar R = radius();
    const auto& pos = sys.positions();
    const auto& rad = sys.radii();
    List<scalar> bGas(n, Zero);
    const vansCloud* cloud = cloud_;
    const volScalarField* KpPtr = cloud ? &cloud->Kp() : nullptr;
    const volScalarField* epsPtr = cloud ? &cloud->voidFraction() : nullptr;
    if (history && KpPtr && epsPtr)
    {
        const grainCloud& grains = cloud->grains();
        const bool decomposed = grains.decomposed();
        const scalar zc = mesh_.bounds().centre().z();
        for (label g = 0; g < n; ++g)
        {
            if (decomposed && !grains.owned(g))
            {
                continue;
            }
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
        if (decomposed)
        {
            grainTools::sumOverCopies(cloud_->grains(), bGas);
        }
        else
        {
            Pstream::listCombineGather(bGas, maxEqOp<scalar>());
            Pstream::listCombineScatter(bGas);
        }
    }
    return bGas;
}


Foam::vector Foam::vapourDroplet::otherForcePredictor
(
    const label g,
    const vector& v,
    const scalar mi,
    const scalar b,
    const grainLinearForces& lf,
    vector& gasChange
) const
{
    // other forces of the previous step (contacts, gas), eq. 3.46 p^n
    vector P = mi*(v - lf.v1[g])/prevDt_ - mi*lf.gGrain - lf.F1[g];
    // change of vansCloud's gas force over the step
    // (vapourDroplet.H, "Gas drag of the grains inside"):
    //   G^n - G^{n-1} = b_i (G^{n-1} - G^{n-2}
    //     - m_i (2 dv^n - dv^{n-1})/dt),  dv^n = v^n - v^{n-1}
    const vector dvn = v - lf.v1[g];
    const vector dvp = lf.history2 ? vector(lf.v1[g] - lf.v2[g]) : vector(Zero);
    const vector dGp = lf.history2 ? lf.dG[g] : vector(Zero);
    gasChange = b*(dGp - mi*(2*dvn - dvp)/lf.dt);
    if (lf.twoD)
    {
        gasChange.z() = 0;
    }
    P += gasChange;
    return P;
}


void Foam::vapourDroplet::addGrainCoefficients
(
    const nscd::System& sys,
    const label g,
    const scalar b,
    const bool owned,
    grainLinearForces& lf
)
{
    const auto& pos = sys.positions();
    const auto& vel = sys.velocities();
    const bool twoD = lf.twoD;
    const double dx = pos[g][0] - x_.x();
    const double dy = pos[g][1] - x_.y();
    const double dz = twoD ? 0.0 : pos[g][2] - x_.z();
    const scalar r = sys.radii()[g];
    const scalar lens =
        lensOverlap(lf.R, r, std::sqrt(dx*dx + dy*dy + dz*dz), twoD);
    if (!(lens > 0))
    {
        return;
    }
    const vector& un = lf.un;
    const scalar dt = lf.dt;
    const scalar Vg = twoD ? pi*r*r : 4.0/3.0*pi*r*r*r;
    const scalar f = min(lens/Vg, scalar(1));
    const vector v(vel[g][0], vel[g][1], twoD ? 0.0 : vel[g][2]);
    const scalar d = 2*r;
    const scalar Re = rhoL_*mag(un - v)*d/muL_;
    const scalar gam = drag_->gamma(lf.epsL, Re, d, muL_, rhoL_, twoD);
    // liquid-displacing volume a_i = f_i (1 - n) V_i (2D: per depth)
    const scalar a = f*(1 - porosity_)*Vg;
    const scalar ci = a*gam;
    scalar& k = lf.k[g];
    vector& e = lf.e[g];
    scalar& w = lf.w[g];
    if (sys.fixed(g))
    {
        // fixed grain (infinite mass): backward Euler drag
        // c_i (u - v_i) and the full pressure share a_i S/V
        k = ci;
        e = ci*(un - v);
        w = a/lf.V;
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
        // absorbedGrains carried: the coupling rate c/(1 - f), infinite
        // once the grain is fully inside (f = 1): phi = 0, phi c = m/dt,
        // so F_i = m (u - v^n)/dt - (m g + P) gives the grain the
        // droplet's velocity and puts its mass, weight and other forces
        // into the droplet's equation; the liquid's pressure on it
        // (w = phi a/V) vanishes, its buoyancy in the liquid being
        // internal to the combined body (README, "The model")
        scalar phi = 0;
        scalar phiC = mi/dt;
        if (!carryGrains_ || f < 1 - 1e-12)
        {
            const scalar carry = carryGrains_ ? 1 - f : 1;
            const scalar x = ci*dt/(mi*carry);
            phi = x > 1e-12 ? -std::expm1(-x)/x : 1.0;
            // phi c' = (1 - e^{-x}) m/dt, c' = c/carry the coupling rate
            phiC = carryGrains_ ? -std::expm1(-x)*mi/dt : phi*ci;
        }
        vector P(Zero);
        if (lf.history)
        {
            P = otherForcePredictor(g, v, mi, b, lf, lf.gasChange[g]);
        }
        k = (1 - phi)*mi/dt;
        e = phiC*(un - v) - (1 - phi)*(mi*lf.gGrain + P);
        w = phi*a/lf.V;
    }
    if (twoD)
    {
        e.z() = 0;
    }
    lf.inside[g] = true;
    if (owned)
    {
        lf.C += lf.depth*k;
        lf.W += lf.depth*w;
        lf.Bv += lf.depth*(k*un - e);
        ++nGrainsIn_;
    }
}


Foam::UList<Foam::vector> Foam::vapourDroplet::history(const label k) const
{
    return cloud_->grains().column<vector>(historyColumns[k]);
}


void Foam::vapourDroplet::grainForceCoefficients
(
    const grainCloud& cloud,
    grainLinearForces& lf
)
{
    const nscd::System& sys = cloud.system();
    lf.sys = &sys;
    lf.grains = &cloud;
    lf.n = sys.size();
    const label n = lf.n;
    // the predictor history: columns that follow the grains (declareGrain
    // History: removal at outlet patches, renumbering, grainState.h5)
    lf.v1.shallowCopy(cloud.column<vector>(historyColumns[0]));
    lf.F1.shallowCopy(cloud.column<vector>(historyColumns[1]));
    lf.v2.shallowCopy(cloud.column<vector>(historyColumns[2]));
    lf.dG.shallowCopy(cloud.column<vector>(historyColumns[3]));
    if (!restartHistory_.empty())
    {
        restoreGrainHistory(sys);
    }
    grainForce_.setSize(n);
    grainForce_ = Zero;
    lf.k.setSize(n, Zero);
    lf.e.setSize(n, Zero);
    lf.w.setSize(n, Zero);
    lf.inside.setSize(n, false);
    // liquid fraction of the droplet (liquid + absorbed grains, eq. 4.15)
    lf.epsL = max(1 - (1 - porosity_)*Vp_/lf.V, scalar(1e-3));
    lf.gGrain = vector(sys.gravity()[0], sys.gravity()[1], sys.gravity()[2]);
    // other forces of the previous step (contacts, gas), eq. 3.46 p^n
    lf.history = history_ && prevDt_ > 0;
    lf.history2 = lf.history && history2_;
    lf.gasChange.setSize(n, Zero);

    const List<scalar> bGas(gasRelaxationFactors(sys, lf.history));
    for (label g = 0; g < n; ++g)
    {
        addGrainCoefficients(sys, g, bGas[g], cloud.owned(g), lf);
    }
    // the droplet sums over every grain once: each rank's owned grains,
    // summed over the ranks (the same on every rank, as the droplet)
    if (cloud.decomposed())
    {
        reduce(lf.C, sumOp<scalar>());
        reduce(lf.W, sumOp<scalar>());
        reduce(lf.Bv, sumOp<vector>());
        reduce(nGrainsIn_, sumOp<label>());
    }
    // the liquid keeps a share 1 - W > 0 of S (round-off guard for a
    // droplet with almost no liquid left: cap W at 1 - 1e-3 by scaling
    // all w_i, which keeps F_p = -depth sum F_i exact)
    const scalar Wmax = 1 - 1e-3;
    if (lf.W > Wmax)
    {
        const scalar s = Wmax/lf.W;
        forAll(lf.w, g)
        {
            lf.w[g] *= s;
        }
        lf.W = Wmax;
    }
}


void Foam::vapourDroplet::solveDropletVelocity
(
    const bool move,
    const vector& gVec,
    const grainLinearForces& lf,
    vector& u
)
{
    const scalar dt = lf.dt;
    const scalar C = lf.C;
    const vector& Bv = lf.Bv;
    const vector& un = lf.un;
    const scalar beta = 1 - lf.W;

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
}


void Foam::vapourDroplet::applyGrainForces
(
    const grainLinearForces& lf,
    const vector& u
)
{
    const label n = lf.n;
    const bool twoD = lf.twoD;
    const auto& vel = lf.sys->velocities();

    // F_i = k_i (u^{n+1} - u^n) + e_i + w_i S on every copy of a grain,
    // F_p = -depth sum F_i over every grain once (owned, summed over the
    // ranks when decomposed)
    const grainCloud& grains = *lf.grains;
    vector Fp(Zero);
    for (label g = 0; g < n; ++g)
    {
        if (lf.inside[g])
        {
            vector F = lf.k[g]*(u - lf.un) + lf.e[g] + lf.w[g]*S_;
            if (twoD)
            {
                F.z() = 0;
            }
            grainForce_[g] = F;
            if (grains.owned(g))
            {
                Fp -= lf.depth*F;
            }
        }
    }
    if (grains.decomposed())
    {
        reduce(Fp, sumOp<vector>());
    }
    Fp_ += Fp;
    grainForceTotal_ = -Fp;
    historyGrains_ =
        grains.decomposed() ? returnReduce(n > 0, orOp<bool>()) : n > 0;

    // history for the predictor P of the next step
    // (v^{n-2} of a step without a history: whatever v1 held, unused)
    UList<vector> v1(history(0));
    history(2).deepCopy(v1);
    history(3).deepCopy(lf.gasChange);
    for (label g = 0; g < n; ++g)
    {
        v1[g] = vector(vel[g][0], vel[g][1], twoD ? 0.0 : vel[g][2]);
    }
    history(1).deepCopy(grainForce_);
    history2_ = history_;
    history_ = true;
    prevDt_ = lf.dt;
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
    grainForceTotal_ = Zero;

    // Per grain i (nscd units): the force of the droplet on the grain,
    //   F_i = k_i (u - u^n) + e_i + w_i S,
    // linear in the droplet velocity u = u_d^{n+1} and in the surface
    // force S (see vapourDroplet.H).  Droplet sums (droplet units, x depth
    // in 2D): C = sum k_i [kg/s], Bv = sum (k_i u^n - e_i) [N],
    // W = sum w_i [-] (~ 1 - eps_l), so that
    //   F_p = -depth sum F_i = -C u + Bv - W S.
    grainLinearForces lf;
    lf.dt = dt;
    lf.twoD = adapter_.twoD();
    // nscd works per unit depth in 2D; the droplet over the mesh depth
    lf.depth = lf.twoD ? adapter_.depth() : 1;
    lf.R = radius();
    lf.V = volume() + Vp_;
    lf.un = u_;

    const bool grains =
        grainDrag_ && drag_.valid() && m_ > 0
     && cloud_;
    grainExchange_ = grains;
    if (grains)
    {
        grainForceCoefficients(cloud_->grains(), lf);
    }
    else
    {
        grainForce_.clear();
        history_ = false;
        history2_ = false;
    }

    solveDropletVelocity(move, gVec, lf, u);

    if (grains)
    {
        applyGrainForces(lf, u);
    }
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


// ************************************************************************* //
