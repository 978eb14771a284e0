// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud (see grainCloud.H)

Description
    Construction (mesh dimension, the nscd::System from the saved state or
    empty, walls, gravity from constant/g), the 2D mapping between the nscd
    plane and the mesh mid-plane, the start-state check and evolve(), one
    NSCD step.  Settings, walls, thermal walls, output, outlets and run
    checks are in grainCloudSettings.C, grainCloudWalls.C,
    grainCloudThermalWalls.C, grainCloudIO.C, grainCloudOutlets.C,
    grainCloudChecks.C and grainCloudLeaving.C.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "contactSolverColumns.H"
#include "nscdMPI/DecomposedSystem.H"  // (unique_ptr member: complete type)
#include "grainVectorTools.H"
#include "uniformDimensionedFields.H"
#include "OSspecific.H"

#include <cmath>

using Foam::grainTools::toVec3;

// * * * * * * * * * * * * * * Static Data Members * * * * * * * * * * * * * //

const Foam::word Foam::grainCloud::stateFileName("grainState.h5");
const Foam::word Foam::grainCloud::cloudName("grains");
const Foam::word Foam::grainCloud::registryName("grainCloud");

namespace Foam
{
    defineTypeNameAndDebug(grainCloudReference, 0);
}

const Foam::word Foam::grainCloud::cellHintColumn("grainCellHint");


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

Foam::fileName Foam::grainCloud::createSystem
(
    const bool readState,
    const string& notDecomposable
)
{
    fileName statePath(mesh_.time().timePath()/stateFileName);
    if (Pstream::parRun() && !isFile(statePath))
    {
        // decomposed case: every rank reads the undecomposed case's state
        // (its part of it, or the whole when the grains are replicated)
        statePath =
            mesh_.time().globalPath()/mesh_.time().timeName()/stateFileName;
    }
    try
    {
        if (readState)
        {
            // a missing, damaged or bad file: FatalError naming the
            // previous write that holds a state (grainCloudChecks.C)
            if (partStart(notDecomposable))
            {
                readStatePart(statePath);
            }
            else
            {
                whole_.reset(new nscd::System(readStateFile(statePath)));
            }
            system_ = whole_.get();
            startStatePath_ = statePath;
            if (system_->dimension() != dimension_)
            {
                FatalErrorInFunction
                    << statePath << " holds a " << system_->dimension()
                    << "D grain system but the mesh is " << dimension_ << "D"
                    << exit(FatalError);
            }
            applyDictionaryMaterials(statePath);
        }
        else
        {
            whole_.reset(new nscd::System(dimension_));
            system_ = whole_.get();
            if (declareColumns_)
            {
                declareColumns_(*system_);
            }
            for (const nscd::Material& m : dictionaryMaterials())
            {
                system_->addMaterial(m);
            }
            // temperature of the grains added (e.g. by grainDeposit), used
            // by vansFoam when heat transfer is on (thesis section 4.1)
            if (dict_.found("initialTemperature"))
            {
                system_->setDefaultTemperature
                (
                    dict_.get<scalar>("initialTemperature")
                );
            }
            addMeshWalls();
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Grain system: " << err.what() << exit(FatalError);
    }
    return statePath;
}


void Foam::grainCloud::readGravity()
{
    uniformDimensionedVectorField g
    (
        IOobject
        (
            "g",
            mesh_.time().constant(),
            mesh_,
            IOobject::MUST_READ,
            IOobject::NO_WRITE,
            false
        )
    );
    vector gv = g.value();
    if (dimension_ == 2 && mag(gv.z()) > SMALL)
    {
        FatalErrorInFunction
            << "constant/g has a z component " << gv.z() << " in a 2D case"
            << " (x-y plane)." << exit(FatalError);
    }
    system_->setGravity(toVec3(gv));
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::grainCloud::grainCloud
(
    const fvMesh& mesh,
    bool readState,
    const string& notDecomposable,
    const std::function<void(nscd::System&)>& declareColumns
)
:
    mesh_(mesh),
    dict_
    (
        IOobject
        (
            "grainProperties",
            mesh.time().constant(),
            mesh,
            IOobject::MUST_READ,
            IOobject::NO_WRITE
        )
    ),
    dimension_(mesh.nSolutionD()),
    zMid_(0.5*(mesh.bounds().min().z() + mesh.bounds().max().z())),
    depth_(mesh.bounds().max().z() - mesh.bounds().min().z()),
    maxDisplacementFraction_(0.1),
    declareColumns_(declareColumns),
    exits_(mesh, dimension_, zMid_)
{
    if (dimension_ == 2 && mesh.solutionD()[vector::Z] != -1)
    {
        FatalErrorInFunction
            << "2D meshes must lie in the x-y plane (one cell thick in z,"
            << " empty front and back patches)." << exit(FatalError);
    }
    if (dimension_ < 2)
    {
        FatalErrorInFunction
            << "The mesh is " << dimension_ << "-dimensional; grains need a"
            << " 2D (one cell thick in z, empty front/back) or 3D mesh."
            << exit(FatalError);
    }
    if (dimension_ == 3)
    {
        zMid_ = 0;
        depth_ = 1;
    }

    readSettings();

    const fileName statePath(createSystem(readState, notDecomposable));

    computePatchWallIds();
    readOutletPatches();
    label nMeshWalls = 0;
    forAllConstIters(patchWalls_, iter)
    {
        nMeshWalls += iter.val().size();
    }
    readGates(nMeshWalls);
    if (system_->nWalls() != nMeshWalls + gates_.size())
    {
        FatalErrorInFunction
            << statePath << " has " << system_->nWalls() << " walls but the"
            << " wall patches of the mesh give " << nMeshWalls << "." << nl
            << "    The mesh or wallPatches changed since the state was"
            << " written: re-run grainDeposit." << exit(FatalError);
    }
    readMovingWalls();
    readWallFriction();
    readWallTemperatures();
    readFrontRearWalls();
    applySolverSettings();
    setHeartbeat();

    readGravity();
    selectDecomposition
    (
        readState ? notDecomposable : string("grain deposition")
    );
    // (a search hint: it stays on this rank with its grain, -1 elsewhere)
    addColumn<label>(cellHintColumn, 0u, -1);

    if (!mesh.foundObject<regIOobject>(registryName))
    {
        reference_.reset
        (
            new grainCloudReference
            (
                IOobject
                (
                    registryName,
                    mesh.time().timeName(),
                    mesh,
                    IOobject::NO_READ,
                    IOobject::NO_WRITE,
                    true
                ),
                *this
            )
        );
    }

    Info<< "grainCloud: " << nGrainsTotal()
        << (dimension_ == 2 ? " discs" : " spheres")
        << ", " << system_->nWalls() << " walls from "
        << patchWalls_.size() << " wall patches, "
        << movingWalls_.size() << " moving, " << gates_.size()
        << " gates" << nl << endl;
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::vector Foam::grainCloud::meshPosition(label i) const
{
    return meshPoint(system_->positions()[i]);
}


Foam::point Foam::grainCloud::meshPoint(const nscd::Vec3& x) const
{
    return point(x.x(), x.y(), dimension_ == 2 ? zMid_ : x.z());
}


nscd::Vec3 Foam::grainCloud::toSystem(const vector& p) const
{
    return nscd::Vec3(p.x(), p.y(), dimension_ == 2 ? 0 : p.z());
}


void Foam::grainCloud::checkState() const
{
    const std::vector<double>& r = system_->radii();
    // (decomposed: every grain is in the cells of the rank that owns it)
    labelList found(system_->size(), 1);
    if (!decomposed_)
    {
        for (std::size_t i = 0; i < system_->size(); ++i)
        {
            found[i] = exits_.findCell(meshPosition(i)) >= 0 ? 1 : 0;
        }
        Pstream::listCombineGather(found, maxEqOp<label>());
        Pstream::listCombineScatter(found);
    }
    for (std::size_t i = 0; i < system_->size(); ++i)
    {
        if (!(r[i] > 0))
        {
            FatalErrorInFunction
                << "Grain " << i << " has radius " << r[i] << " <= 0"
                << exit(FatalError);
        }
        const vector p(meshPosition(i));
        if (!found[i])
        {
            FatalErrorInFunction
                << "Grain " << i << " at " << p << " (radius " << r[i]
                << ") is outside the mesh " << mesh_.bounds() << nl
                << "    Fix: move the grain inside the domain (check the"
                << " region of grainDepositDict)." << exit(FatalError);
        }
    }
    try
    {
        system_->checkInitialOverlaps();
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Overlapping grains at start:" << nl << err.what() << nl
            << "    Fix: regenerate the packing with grainDeposit or reduce"
            << " the radii." << exit(FatalError);
    }
}


const nscd::StepReport& Foam::grainCloud::evolve(scalar dt)
{
    setWallVelocities(dt);
    applyFrontRearWalls();
    oldPositions_ = system_->positions();
    // decomposed: grains migrate in the step, so the old positions are
    // found by id
    std::vector<long> oldIds;
    if (decomposed_)
    {
        oldIds = system_->grainIds();
    }
    lastRemoved_.clear();
    try
    {
        report_ =
            decomposed_
          ? advanceDecomposed(dt)
          : system_->advance(dt, maxDisplacementFraction_);
    }
    catch (const std::exception& err)
    {
        FatalErrorInFunction
            << "Grain step at time " << mesh_.time().timeName() << ": "
            << err.what() << nl
            << "    The last written time holds the last good state." << nl
            << "    Fix: if the fluid diverged or deltaT is far too large,"
            << " reduce deltaT or use adjustTimeStep yes with maxCo in"
            << " system/controlDict; if the grains really move this fast,"
            << " raise maxSubSteps in the contactSolver dictionary of "
            << dict_.name() << exit(FatalError);
    }

    for (const nscd::Vec3& x : system_->positions())
    {
        // not Eigen's allFinite: inf - inf raises FE_INVALID (SIGFPE)
        if
        (
            !std::isfinite(x.x())
         || !std::isfinite(x.y())
         || !std::isfinite(x.z())
        )
        {
            FatalErrorInFunction
                << "Non-finite grain position at time "
                << mesh_.time().timeName()
                << ". The last written time holds the last good state." << nl
                << "    Fix: reduce deltaT or maxDisplacementFraction."
                << exit(FatalError);
        }
    }

    recordStepHealth();
    if (decomposed_)
    {
        checkDecomposedInsideMesh(oldPositions_, oldIds);
    }
    else
    {
        checkInsideMesh();
    }

    if (gates_.size())
    {
        const label oldPrecision = Info().precision(17);
        scalarList row;
        forAll(gates_, gatei)
        {
            const vector d(gateDisplacement(gatei));
            Info<< "gate " << gates_[gatei].name << " displacement " << d
                << nl;
            row.append(scalarList({d.x(), d.y(), d.z()}));
        }
        Info().precision(oldPrecision);
        if (gatesFile_)
        {
            gatesFile_->write(row);
        }
    }

    Info<< "NSCD: contacts " << report_.contacts
        << ", sub-steps " << report_.substeps
        << ", sweeps " << report_.sweeps
        << ", residual " << report_.residual
        << (report_.converged ? "" : " (NOT converged)")
        << ", max overlap/d_min "
        << report_.maxOverlap/max(minDiameter(), VSMALL)
        << endl;
    if (report_.substepCause != nscd::StepReport::SubStepCause::None)
    {
        Info<< "NSCD sub-steps set by: "
            << grainTools::subStepCauseText(report_).c_str() << endl;
    }
    if (statisticsFile_)
    {
        scalarList row({scalar(nGrainsTotal())});
        row.append(grainTools::contactSolverValues(report_, minDiameter()));
        row.append(kineticEnergy());
        statisticsFile_->write(row);
    }
    writeOutletRow();

    return report_;
}


void Foam::grainCloud::writeStepStatistics()
{
    const std::string perDepth(dimension_ == 2 ? " (2D: per unit depth)" : "");
    List<stepDataFile::column> columns
    ({
        {"grains", "1", "grains in the domain"}
    });
    columns.append(grainTools::contactSolverColumns());
    columns.append
    ({
        "kineticEnergy", "J",
        "grain kinetic energy (translation + rotation)" + perDepth
    });
    statisticsFile_.reset
    (
        new stepDataFile
        (
            mesh_.time(), "grainStatistics",
            "grains and contact solver per time step (the log's \"NSCD:\""
            " line)",
            columns
        )
    );
    if (gates_.size())
    {
        List<stepDataFile::column> gateColumns;
        for (const gate& g : gates_)
        {
            for (const char* c : {"x", "y", "z"})
            {
                gateColumns.append
                ({
                    g.name + "_" + c, "m",
                    "displacement of gate " + g.name + " from its start, "
                    + c
                });
            }
        }
        gatesFile_.reset
        (
            new stepDataFile
            (
                mesh_.time(), "gates",
                "gate displacements at the end of the step (the log's"
                " \"gate <name> displacement\" lines)",
                gateColumns
            )
        );
    }
}


Foam::scalar Foam::grainCloud::kineticEnergy() const
{
    scalar e = 0;
    for (std::size_t i = 0; i < system_->size(); ++i)
    {
        if (system_->fixed(i) || !owned(i)) continue;
        e += 0.5*system_->mass(i)*system_->velocities()[i].squaredNorm()
           + 0.5*system_->inertia(i)
            *system_->angularVelocities()[i].squaredNorm();
    }
    return decomposed_ ? returnReduce(e, sumOp<scalar>()) : e;
}

// ************************************************************************* //
