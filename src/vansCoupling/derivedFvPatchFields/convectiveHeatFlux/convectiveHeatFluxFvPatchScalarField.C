// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: convectiveHeatFlux (see convectiveHeatFluxFvPatchScalarField.H)
\*---------------------------------------------------------------------------*/

#include "convectiveHeatFluxFvPatchScalarField.H"
#include "addToRunTimeSelectionTable.H"
#include "volFields.H"
#include "IOdictionary.H"
#include "grainDictionaryTools.H"

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::convectiveHeatFluxFvPatchScalarField::readDict
(
    const dictionary& dict
)
{
    grainTools::checkKeywords
    (
        dict,
        {"type", "h", "Tinf", "voidFraction", "value", "patchType"}
    );
    for (const word key : {"h", "Tinf"})
    {
        if (!dict.found(key))
        {
            FatalIOErrorInFunction(dict)
                << "Missing keyword '" << key << "' in " << dict.name()
                << " (patch " << patch().name() << ", field "
                << internalField().name() << ", type " << typeName << ")."
                << nl << "    convectiveHeatFlux needs h [W/(m^2 K)] and"
                << " Tinf [K]: q = h (Tinf - T) into the fluid." << nl
                << "    Fix: add e.g. 'h 350; Tinf 290;'."
                << exit(FatalIOError);
        }
    }
    h_ = dict.get<scalar>("h");
    Tinf_ = dict.get<scalar>("Tinf");
    epsName_ = dict.getOrDefault<word>("voidFraction", "voidFraction");
    if (!(h_ >= 0))
    {
        FatalIOErrorInFunction(dict)
            << "Keyword 'h' in " << dict.name() << " must be >= 0 (heat"
            << " transfer coefficient [W/(m^2 K)]), got " << h_ << nl
            << "    Fix: give a non-negative value (0: adiabatic wall)."
            << exit(FatalIOError);
    }
    if (!(Tinf_ > 0))
    {
        FatalIOErrorInFunction(dict)
            << "Keyword 'Tinf' in " << dict.name() << " must be an absolute"
            << " temperature > 0 [K], got " << Tinf_ << nl
            << "    Fix: give the wall temperature in kelvin."
            << exit(FatalIOError);
    }
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::convectiveHeatFluxFvPatchScalarField::
convectiveHeatFluxFvPatchScalarField
(
    const fvPatch& p,
    const DimensionedField<scalar, volMesh>& iF
)
:
    mixedFvPatchScalarField(p, iF),
    h_(0),
    Tinf_(0),
    epsName_("voidFraction"),
    kappa_(-1)
{
    refValue() = Zero;
    refGrad() = Zero;
    valueFraction() = Zero;
}


Foam::convectiveHeatFluxFvPatchScalarField::
convectiveHeatFluxFvPatchScalarField
(
    const fvPatch& p,
    const DimensionedField<scalar, volMesh>& iF,
    const dictionary& dict
)
:
    mixedFvPatchScalarField(p, iF),
    h_(0),
    Tinf_(0),
    epsName_("voidFraction"),
    kappa_(-1)
{
    readDict(dict);

    refValue() = Tinf_;
    refGrad() = Zero;
    valueFraction() = Zero;

    if (dict.found("value"))
    {
        fvPatchScalarField::operator=(scalarField("value", dict, p.size()));
    }
    else
    {
        fvPatchScalarField::operator=(patchInternalField());
    }
}


Foam::convectiveHeatFluxFvPatchScalarField::
convectiveHeatFluxFvPatchScalarField
(
    const convectiveHeatFluxFvPatchScalarField& ptf,
    const fvPatch& p,
    const DimensionedField<scalar, volMesh>& iF,
    const fvPatchFieldMapper& mapper
)
:
    mixedFvPatchScalarField(ptf, p, iF, mapper),
    h_(ptf.h_),
    Tinf_(ptf.Tinf_),
    epsName_(ptf.epsName_),
    kappa_(ptf.kappa_)
{}


Foam::convectiveHeatFluxFvPatchScalarField::
convectiveHeatFluxFvPatchScalarField
(
    const convectiveHeatFluxFvPatchScalarField& ptf
)
:
    mixedFvPatchScalarField(ptf),
    h_(ptf.h_),
    Tinf_(ptf.Tinf_),
    epsName_(ptf.epsName_),
    kappa_(ptf.kappa_)
{}


Foam::convectiveHeatFluxFvPatchScalarField::
convectiveHeatFluxFvPatchScalarField
(
    const convectiveHeatFluxFvPatchScalarField& ptf,
    const DimensionedField<scalar, volMesh>& iF
)
:
    mixedFvPatchScalarField(ptf, iF),
    h_(ptf.h_),
    Tinf_(ptf.Tinf_),
    epsName_(ptf.epsName_),
    kappa_(ptf.kappa_)
{}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::scalar Foam::convectiveHeatFluxFvPatchScalarField::kappa() const
{
    if (kappa_ < 0)
    {
        const IOdictionary transport
        (
            IOobject
            (
                "transportProperties",
                db().time().constant(),
                db(),
                IOobject::MUST_READ,
                IOobject::NO_WRITE,
                false
            )
        );
        if (!transport.found("kappa"))
        {
            FatalIOErrorInFunction(transport)
                << "Missing keyword 'kappa' (fluid thermal conductivity"
                << " [W/(m K)]) in " << transport.name() << ": the "
                << typeName << " condition of patch " << patch().name()
                << " of field " << internalField().name() << " in "
                << internalField().objectPath() << " needs it." << nl
                << "    Fix: add e.g. 'kappa 0.6;' (the value the energy"
                << " equation uses)."
                << exit(FatalIOError);
        }
        kappa_ = dimensionedScalar
        (
            "kappa", dimPower/dimLength/dimTemperature, transport
        ).value();
        if (!(kappa_ > 0))
        {
            FatalIOErrorInFunction(transport)
                << "kappa in " << transport.name() << " must be > 0, got "
                << kappa_ << exit(FatalIOError);
        }
    }
    return kappa_;
}


Foam::tmp<Foam::scalarField>
Foam::convectiveHeatFluxFvPatchScalarField::kappaEff() const
{
    auto tk = tmp<scalarField>::New(patch().size(), kappa());
    if (epsName_ != "none")
    {
        if (!db().foundObject<volScalarField>(epsName_))
        {
            FatalErrorInFunction
                << "No void fraction field '" << epsName_ << "' for the "
                << typeName << " condition of patch " << patch().name()
                << " of field " << internalField().name() << " in "
                << internalField().objectPath() << nl
                << "    Fix: run it with vansFoam (field voidFraction), set"
                << " 'voidFraction <field>;' to another field, or"
                << " 'voidFraction none;' (weight 1)."
                << exit(FatalError);
        }
        tk.ref() *= patch().lookupPatchField<volScalarField, scalar>(epsName_);
    }
    return tk;
}


Foam::tmp<Foam::scalarField>
Foam::convectiveHeatFluxFvPatchScalarField::heatFlux() const
{
    return h_*(Tinf_ - static_cast<const scalarField&>(*this));
}


void Foam::convectiveHeatFluxFvPatchScalarField::updateCoeffs()
{
    if (updated())
    {
        return;
    }

    const scalarField kdc(kappaEff()*patch().deltaCoeffs());

    refValue() = Tinf_;
    refGrad() = Zero;
    valueFraction() = h_/max(h_ + kdc, VSMALL);

    mixedFvPatchScalarField::updateCoeffs();
}


void Foam::convectiveHeatFluxFvPatchScalarField::write(Ostream& os) const
{
    fvPatchScalarField::write(os);
    os.writeEntry("h", h_);
    os.writeEntry("Tinf", Tinf_);
    if (epsName_ != "voidFraction")
    {
        os.writeEntry("voidFraction", epsName_);
    }
    writeEntry("value", os);
}


// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //

namespace Foam
{
    makePatchTypeField
    (
        fvPatchScalarField,
        convectiveHeatFluxFvPatchScalarField
    );
}

// ************************************************************************* //
