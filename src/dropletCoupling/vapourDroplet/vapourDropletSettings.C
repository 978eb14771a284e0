// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet settings (see vapourDroplet.H)

Description
    constant/dropletProperties (keyword-checked, FatalIOError naming the
    file, the keyword and the fix), the drag law and grain porosity of
    constant/couplingProperties, and the fluid properties of
    constant/transportProperties (rho [kg/m^3], Cp [J/(kg K)], kappa
    [W/(m K)], nu [m^2/s], vapour rho and D).
\*---------------------------------------------------------------------------*/

#include "vapourDroplet.H"
#include "grainDictionaryTools.H"
#include "Switch.H"
#include "mathematicalConstants.H"

#include <cmath>

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

} // End anonymous namespace


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vapourDroplet::readDict()
{
    const wordList allowed
    {
        "centre", "radius", "diameter", "velocity", "liquidDensity",
        "latentHeat", "vapourisationTemperature", "vapourDensity", "moving",
        "blowing", "penalisationFactor", "grainDrag", "liquidViscosity",
        "surfaceTension", "vapourRelease", "filmConduction", "vapourViscosity",
        "absorbedGrains", "liquidConductivity"
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

    rhoL_ = requirePositive
    (
        dict_, "liquidDensity", "liquid density rho_l [kg/m^3]"
    );
    L_ = requirePositive
    (
        dict_, "latentHeat", "latent heat of vaporisation L [J/kg]"
    );
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
    readModelOptions();
    readCouplingProperties();
    readFluidProperties();

    // liquid mass from the radius (eq. 4.15 with V_p = 0)
    const scalar V =
        adapter_.twoD()
      ? pi*R0*R0*adapter_.depth()
      : 4.0/3.0*pi*R0*R0*R0;
    m_ = rhoL_*V;
    y0_ = x_.y();
}


void Foam::vapourDroplet::readModelOptions()
{
    // capillary entry barrier (vapourDroplet.md, "Capillary entry barrier")
    sigma_ = dict_.getOrDefault<scalar>("surfaceTension", 0);
    if (!(sigma_ >= 0) || !std::isfinite(sigma_))
    {
        FatalIOErrorInFunction(dict_)
            << "surfaceTension " << sigma_ << " in " << dict_.name()
            << " must be >= 0 [N/m]." << nl
            << "    Fix: e.g. 'surfaceTension 0.0589;' (water at 100 C) or"
            << " 0 (no capillary barrier)." << exit(FatalIOError);
    }

    // where the vapour leaves the surface (README "The model", Blowing)
    {
        const word release =
            dict_.getOrDefault<word>("vapourRelease", "uniform");
        if
        (
            release != "uniform" && release != "heatFlux"
         && release != "grains"
        )
        {
            FatalIOErrorInFunction(dict_)
                << "vapourRelease " << release << " in " << dict_.name()
                << " is not a release mode." << nl
                << "    Fix: 'vapourRelease uniform;' (uniform blowing over"
                << " the surface, thesis 4.3.2, the default) or"
                << " 'vapourRelease heatFlux;' (vapour leaves where the heat"
                << " entered) or 'vapourRelease grains;' (the vapour of each"
                << " grain's heat leaves in the cells of that grain)."
                << exit(FatalIOError);
        }
        localRelease_ = (release == "heatFlux");
        grainRelease_ = (release == "grains");
    }

    // what the grains inside the droplet are (README, "The model",
    // absorbedGrains): bodies dragged by the liquid, or carried with it
    {
        const word absorbed =
            dict_.getOrDefault<word>("absorbedGrains", "drag");
        if (absorbed != "drag" && absorbed != "carried")
        {
            FatalIOErrorInFunction(dict_)
                << "absorbedGrains " << absorbed << " in " << dict_.name()
                << " is not a mode of the absorbed grains." << nl
                << "    Fix: 'absorbedGrains drag;' (grains inside feel the"
                << " liquid drag law, the default) or 'absorbedGrains"
                << " carried;' (grains inside move with the droplet, their"
                << " mass and weight in its equation)." << exit(FatalIOError);
        }
        carryGrains_ = (absorbed == "carried");
    }

    // the grains' heat exchange with the liquid (vapourDroplet.H; water at
    // 100 C: 0.679 W/(m K), IAPWS 2011 thermal conductivity formulation,
    // Huber et al., J. Phys. Chem. Ref. Data 41 (2012) 033102); not given:
    // as in the gas (the thesis' eq. 4.13)
    kL_ =
        dict_.found("liquidConductivity")
      ? grainTools::getPositive(dict_, "liquidConductivity")
      : -1;

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
            << "    Fix: filmConduction no for a 3D mesh."
            << exit(FatalIOError);
    }
}


void Foam::vapourDroplet::readCouplingProperties()
{
    // drag law and grain porosity of couplingProperties (grains present)
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


void Foam::vapourDroplet::readFluidProperties()
{
    // constant/transportProperties
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
}

// ************************************************************************* //
