// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud output (see grainCloud.H)

Description
    Writes of a time directory: the HDF5 state <time>/grainState.h5 (bit-exact
    restart; written atomically by writeStateFile, grainCloudChecks.C) and
    its entry in <case>/grainState.xmf (ParaView, grainCloudXdmf.C), the
    outlet counts and the lagrangian cloud <time>/lagrangian/grains/
    {positions, d [m], U [m/s], omega [1/s], grainId, fixed, extra fields}
    for foamToVTK and ParaView.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "grainVectorTools.H"
#include "passiveParticleCloud.H"
#include "IOField.H"
#include "OSspecific.H"

using Foam::grainTools::toVector;

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{

//- Write the field name of the cloud: values of the grains ids (per-grain
//  values, one per grain of the system)
template<class Type>
void writeGrainField
(
    const Foam::passiveParticleCloud& cloud,
    const Foam::word& name,
    const Foam::UList<Type>& values,
    const Foam::UList<Foam::label>& ids,
    const bool valid
)
{
    Foam::IOField<Type> f
    (
        cloud.fieldIOobject(name, Foam::IOobject::NO_READ),
        ids.size()
    );
    forAll(ids, k)
    {
        f[k] = values[ids[k]];
    }
    f.write(valid);
}


//- Log the grains each rank's mesh holds (nWritten here: whose lagrangian
//  output it writes; replicated: every rank still solves all grains'
//  contacts), the load balance of a parallel run
void logGrainsPerRank(const Foam::label nWritten)
{
    using namespace Foam;
    labelList perRank(Pstream::nProcs(), 0);
    perRank[Pstream::myProcNo()] = nWritten;
    Pstream::gatherList(perRank);
    if (Pstream::master())
    {
        const scalar mean = scalar(sum(perRank))/perRank.size();
        Info<< "grainCloud: grains per rank " << perRank
            << ", largest/mean "
            << (mean > 0 ? max(perRank)/mean : 0) << endl;
    }
}

} // End anonymous namespace


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainCloud::write
(
    const std::vector<std::pair<word, const List<vector>*>>& extra
) const
{
    write(extra, {});
}


void Foam::grainCloud::write
(
    const std::vector<std::pair<word, const List<vector>*>>& extra,
    const std::vector<std::pair<word, const List<scalar>*>>& extraScalars
) const
{
    const Time& runTime = mesh_.time();
    mkDir(runTime.timePath());

    // HDF5 state. Decomposed: each rank writes its grains into its part,
    // joined by the master into the undecomposed case's grainState.h5 (a
    // run on any number of ranks, or serial, restarts from it;
    // grainCloudStateParts.C). Replicated: every rank holds the whole state
    // and writes its copy; in parallel the master also writes the
    // undecomposed case's, so that reconstructPar gives time directories a
    // serial run continues from
    const fileName global(runTime.globalPath()/runTime.timeName());
    const auto whole = [this](const fileName& path)
    {
        writeStateFile
        (
            path,
            [this](const std::string& tmp, const std::string& header)
            {
                system_->writeHDF5(tmp, header);
                addXdmfDatasets(tmp);
            }
        );
    };
    if (decomposed_)
    {
        writeStateParts(global);
    }
    else
    {
        whole(runTime.timePath()/stateFileName);
        if (Pstream::parRun() && Pstream::master())
        {
            mkDir(global);
            whole(global/stateFileName);
        }
        if (!Pstream::parRun() || Pstream::master())
        {
            writeXdmf(global/stateFileName);
        }
    }
    writeOutletCounts();
    writeCloud(extra, extraScalars);
}


void Foam::grainCloud::writeCloud
(
    const std::vector<std::pair<word, const List<vector>*>>& extra,
    const std::vector<std::pair<word, const List<scalar>*>>& extraScalars
) const
{
    const Time& runTime = mesh_.time();
    mkDir(runTime.timePath());

    // Lagrangian cloud for foamToVTK / ParaView: the grains whose centre
    // lies in this rank's part of the mesh (decomposed: the grains it owns);
    // a centre on a processor boundary is found by both sides: the lowest
    // rank writes it, so that reconstructPar gives every grain once
    passiveParticleCloud cloud(mesh_, cloudName, IDLList<passiveParticle>());
    // origId 0, 1, ... at every write (not a count over the run): the same
    // grains give the same files (the start time is rewritten at start)
    particle::particleCount_ = 0;
    const label n = system_->size();
    const UList<label> cellHint(column<label>(cellHintColumn));
    labelList cells(n, -1);
    labelList owner(n, labelMax);
    for (label i = 0; i < n; ++i)
    {
        if (!owned(i))
        {
            continue;
        }
        cells[i] = exits_.findCellFrom(meshPosition(i), cellHint[i]);
        if (cells[i] >= 0)
        {
            owner[i] = Pstream::myProcNo();
        }
    }
    if (Pstream::parRun() && !decomposed_)
    {
        Pstream::listCombineGather(owner, minEqOp<label>());
        Pstream::listCombineScatter(owner);
    }
    DynamicList<label> ids(n);
    for (label i = 0; i < n; ++i)
    {
        if (cells[i] >= 0 && owner[i] == Pstream::myProcNo())
        {
            cloud.addParticle
            (
                new passiveParticle(mesh_, meshPosition(i), cells[i])
            );
            ids.append(i);
        }
    }

    IOField<scalar> d(cloud.fieldIOobject("d", IOobject::NO_READ), ids.size());
    IOField<vector> U(cloud.fieldIOobject("U", IOobject::NO_READ), ids.size());
    IOField<vector> omega
    (
        cloud.fieldIOobject("omega", IOobject::NO_READ),
        ids.size()
    );
    IOField<label> grainId
    (
        cloud.fieldIOobject("grainId", IOobject::NO_READ),
        ids.size()
    );
    IOField<label> fixed
    (
        cloud.fieldIOobject("fixed", IOobject::NO_READ),
        ids.size()
    );
    forAll(ids, k)
    {
        const label i = ids[k];
        d[k] = 2*system_->radii()[i];
        U[k] = toVector(system_->velocities()[i]);
        omega[k] = toVector(system_->angularVelocities()[i]);
        grainId[k] = label(system_->grainIds()[i]);
        fixed[k] = system_->fixed(i) ? 1 : 0;
    }
    cloud.write();
    if (Pstream::parRun())
    {
        logGrainsPerRank(ids.size());
    }
    const bool valid = ids.size() > 0;
    d.write(valid);
    U.write(valid);
    omega.write(valid);
    grainId.write(valid);
    fixed.write(valid);
    for (const auto& ex : extra)
    {
        writeGrainField(cloud, ex.first, *ex.second, ids, valid);
    }
    for (const auto& ex : extraScalars)
    {
        writeGrainField(cloud, ex.first, *ex.second, ids, valid);
    }
}

// ************************************************************************* //
