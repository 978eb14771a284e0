// SPDX-License-Identifier: GPL-3.0-or-later
#include "undisturbedVelocity.H"
#include "dragModel.H"
#include "overlapMeshAdapter.H"
#include "volFields.H"
#include "mathematicalConstants.H"

#include <cmath>

// * * * * * * * * * * * * * * * Local Functions  * * * * * * * * * * * * * //

namespace
{
    using Foam::scalar;

    // table of phi: log10(Re_sigma) from -4 to 5, 64 points a decade
    constexpr scalar log10ReMin = -4;
    constexpr scalar log10ReMax = 5;
    constexpr int perDecade = 64;

    //- x^2 I(x, R) of the class description (R > 0, x > 0)
    scalar x2I(const scalar x, const scalar R)
    {
        const scalar a = R/x;
        if (a < 1e-2)
        {
            // series in a^2: int (1 - c^2)(1 - a^2 c^2 + a^4 c^4) dc
            return 4.0/3.0 - 4.0/15.0*a*a + 4.0/35.0*a*a*a*a;
        }
        return x*x*(2*(R*R + x*x)*std::atan(a)/(R*x) - 2)/(R*R);
    }

    //- The Fourier integrand x^2 exp(-x^2/2) I(x, R) dx after x = exp(t)
    scalar integrand(const scalar t, const scalar R)
    {
        const scalar x = std::exp(t);
        return x*std::exp(-0.5*x*x)*x2I(x, R);
    }

    Foam::IOobject tmpIO(const Foam::fvMesh& mesh, const Foam::word& name)
    {
        return Foam::IOobject
        (
            name, mesh.time().timeName(), mesh,
            Foam::IOobject::NO_READ, Foam::IOobject::NO_WRITE, false
        );
    }
}


// * * * * * * * * * * * * * * Static Data Members * * * * * * * * * * * * * //

const Foam::wordList Foam::undisturbedVelocity::modelNames
{
    "none", "steadyOseen"
};


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::undisturbedVelocity::undisturbedVelocity
(
    const dictionary& dict,
    const bool twoD
)
:
    model_(model::none)
{
    const word w(dict.getOrDefault<word>("undisturbedVelocity", "none"));
    const label k = modelNames.find(w);
    if (k < 0)
    {
        FatalIOErrorInFunction(dict)
            << "undisturbedVelocity " << w << " in " << dict.name()
            << " is not a correction of the self-induced velocity; allowed: "
            << modelNames << "." << nl
            << "    Fix: undisturbedVelocity none; (the drag with the"
            << " gathered fluid velocity, the default) or undisturbedVelocity"
            << " steadyOseen; (Balachandar, Liu & Lakhote 2019, 3D)"
            << exit(FatalIOError);
    }
    model_ = model(k);
    if (model_ == model::steadyOseen && twoD)
    {
        FatalIOErrorInFunction(dict)
            << "undisturbedVelocity steadyOseen in " << dict.name()
            << " is the self-induced velocity of a point force in 3D; this"
            << " mesh is 2D (one cell thick, empty front and back)." << nl
            << "    Fix: undisturbedVelocity none; in 2D"
            << exit(FatalIOError);
    }
    if (model_ == model::steadyOseen)
    {
        const label n = label((log10ReMax - log10ReMin)*perDecade) + 1;
        phiTable_.setSize(n);
        forAll(phiTable_, j)
        {
            phiTable_[j] =
                oseenFactor(std::pow(10.0, log10ReMin + scalar(j)/perDecade));
        }
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

const Foam::word& Foam::undisturbedVelocity::name() const
{
    return modelNames[label(model_)];
}


Foam::scalar Foam::undisturbedVelocity::oseenFactor(const scalar R)
{
    if (!(R > 0))
    {
        return 1;
    }
    // composite Simpson in t = ln x, from x = 1e-6 min(R, 1) to 12
    // (exp(-72) beyond): the integrand is smooth in t; 400 panels are
    // converged to 1e-10 (200 agree) and match a 2D trapezoid rule in
    // (x, c) to its own accuracy (1e-5 at R <= 1)
    const scalar t0 = std::log(1e-6*Foam::min(R, scalar(1)));
    const scalar t1 = std::log(12.0);
    const label n = 400;
    const scalar h = (t1 - t0)/n;
    scalar s = integrand(t0, R) + integrand(t1, R);
    for (label j = 1; j < n; ++j)
    {
        s += (j % 2 ? 4 : 2)*integrand(t0 + j*h, R);
    }
    const scalar integral = s*h/3;
    return 3/(4*std::sqrt(0.5*constant::mathematical::pi))*integral;
}


Foam::scalar Foam::undisturbedVelocity::oseenFactorTable(const scalar R) const
{
    const label n = phiTable_.size();
    const scalar Rmin = std::pow(10.0, log10ReMin);
    const scalar Rmax = std::pow(10.0, log10ReMax);
    if (!(R > Rmin))
    {
        // phi = 1 - O(R)
        return 1 - (1 - phiTable_[0])*Foam::max(R, scalar(0))/Rmin;
    }
    if (R >= Rmax)
    {
        return phiTable_[n - 1]*Rmax/R;
    }
    const scalar p = (std::log10(R) - log10ReMin)*perDecade;
    const label j = Foam::min(label(p), n - 2);
    const scalar f = p - j;
    return std::exp
    (
        (1 - f)*std::log(phiTable_[j]) + f*std::log(phiTable_[j + 1])
    );
}


void Foam::undisturbedVelocity::updateKernelWidths
(
    const fvMesh& mesh,
    const overlapMeshAdapter& adapter
)
{
    if (model_ == model::none)
    {
        return;
    }
    // moments of the overlap kernel, about the mesh centre (round-off)
    const vector x0(mesh.bounds().centre());
    volVectorField c1
    (
        tmpIO(mesh, "undisturbedVelocity:x"),
        mesh.C() - dimensionedVector("x0", dimLength, x0)
    );
    volScalarField m2
    (
        tmpIO(mesh, "undisturbedVelocity:x2"), mesh,
        dimensionedScalar(dimArea, Zero)
    );
    m2.primitiveFieldRef() =
        magSqr(c1.primitiveField()) + 0.25*pow(mesh.V().field(), 2.0/3.0);
    List<vector> xBar;
    List<scalar> x2;
    adapter.gather(c1, xBar);
    adapter.gather(m2, x2);
    sigma_.setSize(x2.size());
    kappa_.setSize(x2.size());
    kappa_ = 0;
    forAll(sigma_, i)
    {
        // sigma^2 = 2 s^2, s^2 = (x2 - |xBar|^2)/3
        sigma_[i] =
            std::sqrt(Foam::max(2.0/3.0*(x2[i] - magSqr(xBar[i])), 0.0));
    }
}


Foam::scalar Foam::undisturbedVelocity::gamma
(
    const label i,
    const dragModel& drag,
    const scalar eps,
    const scalar ReG,
    const scalar d,
    const scalar mu,
    const scalar rho,
    const scalar W,
    scalar& Re
)
{
    Re = ReG;
    if (model_ == model::none || !(sigma_[i] > 0))
    {
        return drag.gamma(eps, ReG, d, mu, rho);
    }
    if (sigma_[i] < 0.7*d && !warnedNarrow_)
    {
        // measured (docs/validation/drag.md): h/d = 1 gives sigma ~0.6 d
        // and a lone sphere 20 % too slow; h/d >= 2, sigma >= 0.8 d: 4 %
        WarningInFunction
            << "undisturbedVelocity " << name() << ": grain " << i
            << " of diameter " << d << " m has an overlap kernel of width"
            << " sigma " << sigma_[i] << " m < 0.7 d (cells finer than about"
            << " 1.5 d): the correction over-estimates the self-induced"
            << " velocity there (a lone sphere at h/d = 1 settles 20 % too"
            << " slowly, docs/validation/drag.md)." << nl
            << "    Fix: cells of at least 2 d, or undisturbedVelocity none;"
            << " (warned once)" << endl;
        warnedNarrow_ = true;
    }
    using constant::mathematical::pi;
    // kappa = phi(Re_sigma) W gamma/(c mu sigma), c = 3 sqrt(2) pi^(3/2)
    const scalar c = 3*std::sqrt(2.0)*pi*std::sqrt(pi)*mu*sigma_[i];
    scalar g = 0;
    scalar kappa = 0;
    // fixed point Re = ReG/(1 - kappa(Re)): kappa varies slowly with Re
    // (phi and gamma/Re decrease, gamma increases); 50 iterations bound
    for (label it = 0; it < 50; ++it)
    {
        g = drag.gamma(eps, Re, d, mu, rho);
        kappa = Foam::min
        (
            oseenFactorTable(Re*sigma_[i]/d)*W*g/c, kappaMax
        );
        const scalar ReNew = ReG/(1 - kappa);
        const bool done = mag(ReNew - Re) <= 1e-10*Foam::max(Re, SMALL);
        Re = ReNew;
        if (done)
        {
            break;
        }
    }
    g = drag.gamma(eps, Re, d, mu, rho);
    kappa_[i] = kappa;
    return g/(1 - kappa);
}


// ************************************************************************* //
