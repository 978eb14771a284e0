/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDropletSource (see vapourDropletSource.H)
\*---------------------------------------------------------------------------*/

#include "vapourDropletSource.H"
#include "fvMatrices.H"
#include "fvmSup.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"

#include <sstream>

namespace Foam
{
namespace fv
{
    defineTypeNameAndDebug(vapourDropletSource, 0);
    addToRunTimeSelectionTable(option, vapourDropletSource, dictionary);
}
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::fv::vapourDropletSource::update()
{
    if (timeIndex_ == mesh_.time().timeIndex())
    {
        return;
    }
    timeIndex_ = mesh_.time().timeIndex();
    droplet_.update();
    if (volumeSourcePtr_.valid())
    {
        volumeSourcePtr_->field() = droplet_.volumeSource(droplet_.Vdot());
    }
}


Foam::tmp<Foam::volScalarField::Internal>
Foam::fv::vapourDropletSource::Kchi() const
{
    auto tk = tmp<volScalarField::Internal>::New
    (
        IOobject
        (
            name_ + ":Kchi", mesh_.time().timeName(), mesh_,
            IOobject::NO_READ, IOobject::NO_WRITE, false
        ),
        mesh_,
        dimensionedScalar(inv(dimTime), Zero)
    );
    tk.ref().field() = droplet_.K()*droplet_.chi();
    return tk;
}


Foam::tmp<Foam::volScalarField::Internal>
Foam::fv::vapourDropletSource::q() const
{
    auto tq = tmp<volScalarField::Internal>::New
    (
        IOobject
        (
            name_ + ":q", mesh_.time().timeName(), mesh_,
            IOobject::NO_READ, IOobject::NO_WRITE, false
        ),
        mesh_,
        dimensionedScalar(inv(dimTime), Zero)
    );
    if (volumeSourcePtr_.valid())
    {
        tq.ref().field() = volumeSourcePtr_->field();
    }
    return tq;
}


void Foam::fv::vapourDropletSource::addScalar
(
    fvMatrix<scalar>& eqn,
    const label fieldi
)
{
    update();
    const word& f = fieldNames_[fieldi];
    const tmp<volScalarField::Internal> tK(Kchi());
    // target value inside: T_d for T, 1 for the vapour fraction
    const dimensionedScalar target
    (
        "target", eqn.psi().dimensions(),
        f == "T" ? droplet_.Td() : 1.0
    );
    eqn -= fvm::Sp(tK(), eqn.psi());
    eqn += tK()*target;
    if (volumeSourcePtr_.valid())
    {
        eqn += q()*target;
    }
}


void Foam::fv::vapourDropletSource::addVector(fvMatrix<vector>& eqn)
{
    update();
    const tmp<volScalarField::Internal> tK(Kchi());
    const dimensionedVector ud
    (
        "ud", eqn.psi().dimensions(), droplet_.velocity()
    );
    eqn -= fvm::Sp(tK(), eqn.psi());
    eqn += tK()*ud;
    if (volumeSourcePtr_.valid())
    {
        eqn += q()*ud;
    }
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::fv::vapourDropletSource::vapourDropletSource
(
    const word& name,
    const word& modelType,
    const dictionary& dict,
    const fvMesh& mesh
)
:
    option(name, modelType, dict, mesh),
    droplet_(mesh),
    timeIndex_(-1)
{
    read(dict);

    // registered (vansFoam's pEqn.H looks dropletVolumeSource up) and
    // written at the write times
    auto field = [&mesh](const word& name, const dimensionSet& dims)
    {
        return new volScalarField::Internal
        (
            IOobject
            (
                name, mesh.time().timeName(), mesh,
                IOobject::NO_READ, IOobject::AUTO_WRITE, true
            ),
            mesh,
            dimensionedScalar(dims, Zero)
        );
    };
    if (droplet_.blowing())
    {
        volumeSourcePtr_.reset(field("dropletVolumeSource", inv(dimTime)));
    }
    heatSinkPtr_.reset(field("dropletHeatSink", dimPower/dimVolume));
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::fv::vapourDropletSource::addSup
(
    fvMatrix<scalar>& eqn,
    const label fieldi
)
{
    addScalar(eqn, fieldi);
}


void Foam::fv::vapourDropletSource::addSup
(
    const volScalarField&,
    fvMatrix<scalar>& eqn,
    const label fieldi
)
{
    addScalar(eqn, fieldi);
}


void Foam::fv::vapourDropletSource::addSup
(
    fvMatrix<vector>& eqn,
    const label
)
{
    addVector(eqn);
}


void Foam::fv::vapourDropletSource::addSup
(
    const volScalarField&,
    fvMatrix<vector>& eqn,
    const label
)
{
    addVector(eqn);
}


void Foam::fv::vapourDropletSource::correct(volScalarField& field)
{
    if (field.name() != "T")
    {
        return;
    }
    update();
    // heat taken from the fluid by the implicit sink, end-of-step T [W]
    const scalar rhoCp = droplet_.rhoFluid()*droplet_.CpFluid();
    // local heat sink [W/m^3], written as dropletHeatSink
    heatSinkPtr_->field() =
        rhoCp*droplet_.K()*droplet_.chi()
       *(field.primitiveField() - droplet_.Td());
    const scalar Qf = rhoCp*droplet_.K()*gSum
    (
        droplet_.chi()*(field.primitiveField() - droplet_.Td())*mesh_.V()
    );
    droplet_.setHeatSink(heatSinkPtr_->field());
    // the part the grains gave to the penalised fluid (vansCloud's KT, KTTp:
    // grain-to-fluid heat / (rho Cp) = KTTp - KT T, TEqn.H)
    scalar Qp = 0;
    if
    (
        mesh_.foundObject<volScalarField>("KT")
     && mesh_.foundObject<volScalarField>("KTTp")
    )
    {
        const volScalarField& KT = mesh_.lookupObject<volScalarField>("KT");
        const volScalarField& KTTp = mesh_.lookupObject<volScalarField>("KTTp");
        Qp = rhoCp*gSum
        (
            droplet_.chi()
           *(
                KTTp.primitiveField()
              - KT.primitiveField()*field.primitiveField()
            )
           *mesh_.V()
        );
    }
    droplet_.setHeat(Qf - Qp, Qp);
    droplet_.endStep();

    std::ostringstream os;
    os.precision(10);
    os  << "droplet: Q_f = " << Qf - Qp << " W, Q_p = " << Qp << " W, mdot = " << droplet_.mdot()
        << " kg/s, m = " << droplet_.mass() << " kg, R = "
        << droplet_.radius() << " m, Vdot = " << droplet_.Vdot() << " m^3/s";
    Info<< os.str().c_str() << endl;
}


void Foam::fv::vapourDropletSource::correct(volVectorField& U)
{
    update();
    const vector Ff = droplet_.rhoFluid()*droplet_.K()*gSum
    (
        droplet_.chi()*(U.primitiveField() - droplet_.velocity())*mesh_.V()
    );
    droplet_.setFluidForce(Ff);
    if (debug)
    {
        Info<< "droplet: F_pen = " << Ff << " N, max|U| inside = "
            << gMax(mag(U.primitiveField())*pos(droplet_.chi() - 0.5))
            << endl;
    }
}


bool Foam::fv::vapourDropletSource::read(const dictionary& dict)
{
    if (!option::read(dict))
    {
        return false;
    }
    const wordList allowed
    {
        "type", "active", "log", "libs", word(typeName + "Coeffs")
    };
    grainTools::checkKeywords(dict, allowed);
    if (dict.isDict(typeName + "Coeffs"))
    {
        grainTools::checkKeywords(dict.subDict(typeName + "Coeffs"), wordList{});
    }

    if (!mesh_.foundObject<volScalarField>("T"))
    {
        FatalIOErrorInFunction(dict)
            << "fvOption " << name_ << " (" << typeName << ") needs the fluid"
            << " temperature T: the droplet vaporises by the heat it takes"
            << " from the fluid (thesis eq. 4.16)." << nl
            << "    Fix: switch heat transfer on (couplingProperties"
            << " heatTransferModel, transportProperties Cp and kappa, 0/T)."
            << exit(FatalIOError);
    }
    DynamicList<word> fields;
    fields.append("T");
    if (mesh_.foundObject<volVectorField>("U"))
    {
        fields.append("U");
    }
    if (mesh_.foundObject<volScalarField>("psi"))
    {
        fields.append("psi");
    }
    fieldNames_.transfer(fields);
    applied_.setSize(fieldNames_.size(), false);
    return true;
}


// ************************************************************************* //
