// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDropletSource (see vapourDropletSource.H)
\*---------------------------------------------------------------------------*/

#include "vapourDropletSource.H"
#include "fvMatrices.H"
#include "fvmSup.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"
#include "vansCloud.H"

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

template<class Type>
void Foam::fv::vapourDropletSource::addPerGrain
(
    const List<Type>& mine,
    List<Type>& to
) const
{
    if (mine.empty())
    {
        return;
    }
    if (to.empty())
    {
        to = mine;
        return;
    }
    if (to.size() != mine.size())
    {
        FatalErrorInFunction
            << name_ << ": " << mine.size() << " per-grain values for a list"
            << " of " << to.size() << " grains" << exit(FatalError);
    }
    forAll(to, i)
    {
        to[i] += mine[i];
    }
}


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
    timeIndex_(-1),
    cloud_(nullptr),
    heatIndex_(-1),
    Qf_(0),
    Qp_(0)
{
    read(dict);

    // registered for the output at the write times
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
    if (!cloud_)
    {
        FatalErrorInFunction
            << "fvOption " << name_ << " (" << typeName << ") is not coupled"
            << " to grains: the droplet's step runs in the coupling step of"
            << " a solver that gives its grainCouplingSources to a vansCloud."
            << nl << "    Fix: run vansFoam." << exit(FatalError);
    }
    update();
    heatIndex_ = mesh_.time().timeIndex();
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
    const scalar Qp = rhoCp*gSum
    (
        droplet_.chi()
       *(
            cloud_->KTTp().primitiveField()
          - cloud_->KT().primitiveField()*field.primitiveField()
        )
       *mesh_.V()
    );
    // liquidConductivity: the grains' extra heat to the liquid (into
    // the grains' heat sources and mdot with Q_film)
    droplet_.setLiquidHeat();
    // vapourRelease grains: each grain's part of Q_p (the same sum)
    if (droplet_.grainRelease())
    {
        const scalar sumQi = droplet_.setGrainHeat(field.primitiveField());
        if (debug)
        {
            Info<< "droplet: sum of the grains' heat " << sumQi
                << " W, Q_p " << Qp << " W" << endl;
        }
    }
    // given to the droplet in its step (beforeGrainStep)
    Qf_ = Qf - Qp;
    Qp_ = Qp;
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
        grainTools::checkKeywords
        (
            dict.subDict(typeName + "Coeffs"),
            wordList{}
        );
    }

    return true;
}


// * * * * * * * * * * * * * * * Coupling hooks  * * * * * * * * * * * * * //

void Foam::fv::vapourDropletSource::attach(vansCloud& cloud)
{
    if (!cloud.heatOn())
    {
        FatalIOErrorInFunction(dict_)
            << "fvOption " << name_ << " (" << typeName << ") needs the fluid"
            << " temperature T: the droplet vaporises by the heat it takes"
            << " from the fluid (thesis eq. 4.16)." << nl
            << "    Fix: switch heat transfer on (couplingProperties"
            << " heatTransferModel, transportProperties Cp and kappa, 0/T)."
            << exit(FatalIOError);
    }
    // the fields the coupled solver solves: T (heat on), U, psi (vapour on)
    fieldNames_.setSize(cloud.vapourOn() ? 3 : 2);
    fieldNames_[0] = "T";
    fieldNames_[1] = "U";
    if (cloud.vapourOn())
    {
        fieldNames_[2] = "psi";
    }
    applied_.setSize(fieldNames_.size(), false);
    cloud_ = &cloud;
    droplet_.attach(cloud);
}


Foam::word Foam::fv::vapourDropletSource::couplingName() const
{
    return word(typeName + " " + name_);
}


Foam::string Foam::fv::vapourDropletSource::replicatedGrainsReason() const
{
    // every setting works on decomposed grains (vapourDroplet: sums over the
    // owned grains reduced, per-grain lists completed over a grain's copies)
    return string();
}


void Foam::fv::vapourDropletSource::addGrainHeat(List<scalar>& Q) const
{
    addPerGrain(droplet_.heatIntoGrains(), Q);
}


void Foam::fv::vapourDropletSource::beforeGrainStep(const scalar)
{
    // the droplet step follows the heat of this step (correct(T))
    if (heatIndex_ != mesh_.time().timeIndex())
    {
        return;
    }
    // mass balance (eq. 4.16), then momentum exchange and motion
    droplet_.setHeat(Qf_, Qp_);
    {
        std::ostringstream os;
        os.precision(10);
        os  << "droplet: Q_f = " << Qf_ << " W, Q_p = " << Qp_
            << " W, mdot = " << droplet_.mdot() << " kg/s, m = "
            << droplet_.mass() << " kg, R = " << droplet_.radius()
            << " m, Vdot = " << droplet_.Vdot() << " m^3/s";
        Info<< os.str().c_str() << endl;
    }
    droplet_.endStep();

    if (droplet_.grainExchange())
    {
        const vector& sumF = droplet_.forceOnGrainsTotal();
        std::ostringstream os;
        os.precision(16);
        os  << "droplet-grain force: sum over grains = (" << sumF.x()
            << ' ' << sumF.y() << ' ' << sumF.z() << ") N";
        Info<< os.str().c_str() << endl;
    }
}


void Foam::fv::vapourDropletSource::addGrainForces(List<vector>& F) const
{
    addPerGrain(droplet_.forceOnGrains(), F);
}


void Foam::fv::vapourDropletSource::afterGrainStep()
{
    droplet_.afterGrainStep();
}

// ************************************************************************* //
