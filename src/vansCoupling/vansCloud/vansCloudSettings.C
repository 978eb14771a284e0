// SPDX-License-Identifier: GPL-3.0-or-later
#include "vansCloudSettings.H"
#include "grainDictionaryTools.H"
#include "dimensionedScalar.H"
#include "dimensionSets.H"

#include <cmath>

// * * * * * * * * * * * * * * Static Data Members * * * * * * * * * * * * * //

const Foam::wordList Foam::vansCloudSettings::couplingKeywords
{
    "dragModel", "DallavalleDiFeliceCoeffs", "GidaspowCoeffs",
    "twoDimensionalDrag",
    "voidFraction", "forceModel",
    "heatTransferModel", "DiFeliceColburnCoeffs", "GunnCoeffs",
    "RanzMarshallCoeffs", "cohesion", "rotationCoupling",
    "resolvedCellsPerDiameter", "grainPorosity", "rigidViscosityRatio",
    "pressureDiffusion", "undisturbedVelocity"
};


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::vansCloudSettings::vansCloudSettings(const IOdictionary& dict)
:
    rotation(dict.getOrDefault<bool>("rotationCoupling", false)),
    forceModel(dict.getOrDefault<word>("forceModel", "A")),
    // default: off (no grain resolved; see vansCloud.H, Resolved grains)
    resolvedCellsPerDiameter
    (
        dict.getOrDefault<scalar>("resolvedCellsPerDiameter", GREAT)
    ),
    // default 1000, 0 with rotationCoupling (the rigid interior's limit for
    // spin transients, docs/validation/resolvedGrains.md); only used with
    // resolved grains
    rigidViscosityRatio
    (
        dict.getOrDefault<scalar>("rigidViscosityRatio", rotation ? 0 : 1000)
    )
{
    grainTools::checkKeywords(dict, couplingKeywords);
    grainPorosity = dict.getOrDefault<scalar>("grainPorosity", 0);
    if (!(grainPorosity >= 0 && grainPorosity < 1))
    {
        FatalIOErrorInFunction(dict)
            << "grainPorosity " << grainPorosity << " in " << dict.name()
            << " must be >= 0 and < 1 (porosity n of the grains: the fluid"
            << " sees (1 - n) of each grain's volume, thesis 4.3.2)." << nl
            << "    Fix: e.g. grainPorosity 0.5; (default 0: solid grains)"
            << exit(FatalIOError);
    }
    if (!(resolvedCellsPerDiameter >= 0))
    {
        FatalIOErrorInFunction(dict)
            << "resolvedCellsPerDiameter " << resolvedCellsPerDiameter
            << " in " << dict.name() << " must be >= 0." << nl
            << "    Fix: resolvedCellsPerDiameter 4; (grains spanning 4 or"
            << " more cells per diameter get the resolved solid flux, 0: all"
            << " grains; remove the keyword to switch it off)"
            << exit(FatalIOError);
    }
    pressureDiffusion = dict.getOrDefault<scalar>("pressureDiffusion", 0);
    if (!(pressureDiffusion >= 0))
    {
        FatalIOErrorInFunction(dict)
            << "pressureDiffusion " << pressureDiffusion << " in "
            << dict.name() << " must be >= 0 (artificial pressure diffusion"
            << " C dt of the mixture continuity, relative to the time step;"
            << " 0: off)." << nl
            << "    Fix: pressureDiffusion 1; with voidFraction { method"
            << " centroid; } (remove the keyword to switch it off)"
            << exit(FatalIOError);
    }
    if (!(rigidViscosityRatio >= 0))
    {
        FatalIOErrorInFunction(dict)
            << "rigidViscosityRatio " << rigidViscosityRatio
            << " in " << dict.name() << " must be >= 0 (viscosity"
            << " nu (1 + lambda) inside resolved free grains)." << nl
            << "    Fix: rigidViscosityRatio 1000; (0: off)"
            << exit(FatalIOError);
    }
    if (forceModel != "A" && forceModel != "B")
    {
        FatalIOErrorInFunction(dict)
            << "forceModel " << forceModel << " in " << dict.name()
            << ": use A (eq. 3.23, -eps grad p in the fluid) or B (eq. 3.24)"
            << exit(FatalIOError);
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vapourSettings::read(const dictionary& td)
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
    D = dimensionedScalar("D", dimViscosity, vd).value();
    rho = dimensionedScalar("rho", dimDensity, vd).value();
    if (!(D >= 0) || !std::isfinite(D))
    {
        FatalIOErrorInFunction(vd)
            << "D " << D << " in " << vd.name() << ": the vapour diffusion"
            << " coefficient must be >= 0 [m^2/s]" << exit(FatalIOError);
    }
    if (!(rho > 0) || !std::isfinite(rho))
    {
        FatalIOErrorInFunction(vd)
            << "rho " << rho << " in " << vd.name() << ": the vapour density"
            << " must be > 0 [kg/m^3]" << exit(FatalIOError);
    }
    bounded = vd.getOrDefault<bool>("bounded", false);
    on = true;
}


// ************************************************************************* //
