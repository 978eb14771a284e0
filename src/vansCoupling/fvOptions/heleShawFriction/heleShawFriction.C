// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: heleShawFriction (see heleShawFriction.H)
\*---------------------------------------------------------------------------*/

#include "heleShawFriction.H"
#include "fvMatrices.H"
#include "fvmSup.H"
#include "IOdictionary.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"

// * * * * * * * * * * * * * Static Member Functions * * * * * * * * * * * * //

namespace Foam
{
namespace fv
{
    defineTypeNameAndDebug(heleShawFriction, 0);

    addToRunTimeSelectionTable
    (
        option,
        heleShawFriction,
        dictionary
    );
}
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

Foam::tmp<Foam::volScalarField::Internal>
Foam::fv::heleShawFriction::coefficient(const volScalarField* w) const
{
    auto tcoeff = tmp<volScalarField::Internal>::New
    (
        IOobject
        (
            name_ + ":heleShawFriction",
            mesh_.time().timeName(),
            mesh_,
            IOobject::NO_READ,
            IOobject::NO_WRITE,
            false
        ),
        mesh_,
        dimensionedScalar(inv(dimTime), Zero)
    );
    scalarField& c = tcoeff.ref().field();
    const scalar k = gammaByRho();
    for (const label celli : cells_)
    {
        c[celli] = w ? k*(*w)[celli] : k;
    }
    return tcoeff;
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::fv::heleShawFriction::heleShawFriction
(
    const word& name,
    const word& modelType,
    const dictionary& dict,
    const fvMesh& mesh
)
:
    cellSetOption(name, modelType, dict, mesh),
    gap_(0),
    nu_(0)
{
    read(dict);
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::fv::heleShawFriction::addSup
(
    fvMatrix<vector>& eqn,
    const label fieldi
)
{
    eqn -= fvm::Sp(coefficient(nullptr), eqn.psi());
}


void Foam::fv::heleShawFriction::addSup
(
    const volScalarField& eps,
    fvMatrix<vector>& eqn,
    const label fieldi
)
{
    if (!eps.dimensions().dimensionless())
    {
        FatalErrorInFunction
            << "fvOption " << name_ << " (heleShawFriction) is written for the"
            << " kinematic VANS momentum equation: its weight must be the"
            << " void fraction (dimensionless), got " << eps.name() << " "
            << eps.dimensions() << nl
            << "    Fix: call fvOptions(eps, U) or fvOptions(U) in the solver."
            << exit(FatalError);
    }
    eqn -= fvm::Sp(coefficient(&eps), eqn.psi());
}


bool Foam::fv::heleShawFriction::read(const dictionary& dict)
{
    if (!cellSetOption::read(dict))
    {
        return false;
    }

    const wordList allowed
    {
        "type", "active", "log", "libs", "selectionMode", "cellSet",
        "cellZone", "points", "timeStart", "duration", "fields", "gap", "nu",
        word(typeName + "Coeffs")
    };
    grainTools::checkKeywords(dict, allowed);
    if (&coeffs_ != &dict)
    {
        grainTools::checkKeywords(coeffs_, allowed);
    }

    // fields: one vector field (default U)
    fieldNames_ = coeffs_.getOrDefault<wordList>("fields", wordList{"U"});
    if (fieldNames_.size() != 1)
    {
        FatalIOErrorInFunction(coeffs_)
            << "Keyword 'fields' in " << coeffs_.name() << " lists "
            << fieldNames_.size() << " fields: the Hele-Shaw friction"
            << " applies to the one fluid velocity field." << nl
            << "    Fix: remove 'fields' (default (U)) or give one name."
            << exit(FatalIOError);
    }
    applied_.setSize(fieldNames_.size(), false);

    // gap p [m] (thesis eq. 4.14: gamma = 12 mu/p^2)
    if (!coeffs_.found("gap"))
    {
        FatalIOErrorInFunction(coeffs_)
            << "Missing keyword 'gap' in " << coeffs_.name()
            << " (fvOption " << name_ << ", type " << typeName << ")." << nl
            << "    It is the Hele-Shaw gap p [m] between the front and rear"
            << " walls: gamma = 12 mu/p^2 (thesis eq. 4.14)." << nl
            << "    Fix: add e.g. 'gap 0.015;'."
            << exit(FatalIOError);
    }
    gap_ = coeffs_.get<scalar>("gap");
    if (!(gap_ > 0))
    {
        FatalIOErrorInFunction(coeffs_)
            << "Keyword 'gap' in " << coeffs_.name() << " must be > 0 (the"
            << " Hele-Shaw gap p [m]), got " << gap_ << nl
            << "    Fix: give the distance between the front and rear walls,"
            << " e.g. 'gap 0.015;'."
            << exit(FatalIOError);
    }

    // nu [m^2/s]: keyword, else constant/transportProperties
    if (coeffs_.found("nu"))
    {
        nu_ = coeffs_.get<scalar>("nu");
        if (!(nu_ > 0))
        {
            FatalIOErrorInFunction(coeffs_)
                << "Keyword 'nu' in " << coeffs_.name() << " must be > 0"
                << " (kinematic viscosity [m^2/s]), got " << nu_ << nl
                << "    Fix: correct it or remove it to use nu of"
                << " constant/transportProperties."
                << exit(FatalIOError);
        }
    }
    else
    {
        const IOdictionary transport
        (
            IOobject
            (
                "transportProperties",
                mesh_.time().constant(),
                mesh_,
                IOobject::MUST_READ,
                IOobject::NO_WRITE,
                false
            )
        );
        nu_ = dimensionedScalar("nu", dimViscosity, transport).value();
        if (!(nu_ > 0))
        {
            FatalIOErrorInFunction(transport)
                << "nu in " << transport.name() << " must be > 0 for the"
                << " Hele-Shaw friction " << name_ << ", got " << nu_
                << exit(FatalIOError);
        }
    }

    Info<< "    heleShawFriction " << name_ << ": gap " << gap_
        << " m, nu " << nu_ << " m^2/s, 12 nu/p^2 = " << gammaByRho()
        << " 1/s on " << returnReduce(cells_.size(), sumOp<label>())
        << " cells" << endl;

    return true;
}


// ************************************************************************* //
