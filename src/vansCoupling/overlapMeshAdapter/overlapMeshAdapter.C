// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: overlapMeshAdapter (see overlapMeshAdapter.H): settings,
  construction (mesh view, processor-boundary cells) and the field
  operations (solid and void fraction, solid velocity, spread, gather); the
  mapping itself is in overlapMeshAdapterMap.C
\*---------------------------------------------------------------------------*/

#include "overlapMeshAdapter.H"
#include "grainDictionaryTools.H"

#include "processorPolyPatch.H"
#include "zeroGradientFvPatchFields.H"
#include "Pstream.H"
#include "ops.H"

#include <algorithm>
#include <stdexcept>

namespace om = overlapMapping;

// * * * * * * * * * * * * * * Static Data Members * * * * * * * * * * * * * //

const Foam::wordList Foam::overlapMeshAdapter::keywords
({
    "method", "epsMin", "effectiveDiameterFactor"
});


// * * * * * * * * * * * * * Static Member Functions * * * * * * * * * * * * //

overlapMapping::MappingSettings Foam::overlapMeshAdapter::readSettings
(
    const dictionary& dict
)
{
    grainTools::checkKeywords(dict, keywords);

    om::MappingSettings s;
    const word method(dict.getOrDefault<word>("method", "overlap"));
    if (method == "overlap")
    {
        s.method = om::MappingMethod::Exact;
    }
    else if (method == "centroid")
    {
        s.method = om::MappingMethod::ParticleCentroid;
    }
    else
    {
        FatalIOErrorInFunction(dict)
            << "Unknown mapping method '" << method << "' in "
            << dict.name() << nl
            << "    Valid methods: overlap (exact grain/cell overlaps,"
            << " eq. 3.43) or centroid (particle-centroid method, eq. 3.44)"
            << exit(FatalIOError);
    }
    s.epsMin = grainTools::getPositiveOrDefault(dict, "epsMin", 1e-8);
    if (s.epsMin >= 1)
    {
        FatalIOErrorInFunction(dict)
            << "epsMin " << s.epsMin << " in " << dict.name()
            << " must be in (0, 1) (typical: 1e-8)" << exit(FatalIOError);
    }
    s.effectiveDiameterFactor =
        grainTools::getPositiveOrDefault(dict, "effectiveDiameterFactor", 1);
    s.computeCentroids = false;
    s.outside = om::OutsideGrainPolicy::Skip;
    return s;
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::overlapMeshAdapter::buildMeshView(om::MeshView& view) const
{
    const pointField& pts = mesh_.points();
    view.points.resize(pts.size());
    forAll(pts, i)
    {
        view.points[i] = om::Vec3(pts[i].x(), pts[i].y(), pts[i].z());
    }

    const faceList& faces = mesh_.faces();
    view.faceOffsets.resize(faces.size() + 1);
    view.faceOffsets[0] = 0;
    label nv = 0;
    forAll(faces, f)
    {
        nv += faces[f].size();
        view.faceOffsets[f + 1] = nv;
    }
    view.faceVertices.resize(nv);
    nv = 0;
    for (const face& f : faces)
    {
        for (const label p : f)
        {
            view.faceVertices[nv++] = p;
        }
    }

    const labelList& own = mesh_.faceOwner();
    const labelList& nei = mesh_.faceNeighbour();
    view.owner.assign(own.begin(), own.end());
    view.neighbour.assign(faces.size(), -1);
    forAll(nei, f)
    {
        view.neighbour[f] = nei[f];
    }

    // Centres and volumes of the fvMesh, so both sides agree on V_c
    const volVectorField& C = mesh_.C();
    const scalarField& V = mesh_.V();
    view.cellCentres.resize(mesh_.nCells());
    view.cellVolumes.resize(mesh_.nCells());
    forAll(V, c)
    {
        const vector& x = C[c];
        view.cellCentres[c] = om::Vec3(x.x(), x.y(), x.z());
        view.cellVolumes[c] = V[c];
    }

    view.twoD = twoD_;
    view.z0 = z0_;
    view.z1 = z1_;
}


void Foam::overlapMeshAdapter::findProcCells()
{
    procCells_.clear();
    std::vector<char> mark(mesh_.nCells(), 0);
    for (const polyPatch& pp : mesh_.boundaryMesh())
    {
        if (isA<processorPolyPatch>(pp))
        {
            for (const label c : pp.faceCells())
            {
                if (!mark[c])
                {
                    mark[c] = 1;
                    procCells_.push_back(c);
                }
            }
        }
    }
    const double big = 1e300;
    procMin_ = om::Vec3(big, big, big);
    procMax_ = om::Vec3(-big, -big, -big);
    for (const om::label c : procCells_)
    {
        const om::Vec3& b = cellMesh_->boundCentre(c);
        const double R = cellMesh_->boundRadius(c);
        for (int k = 0; k < 3; ++k)
        {
            procMin_[k] = std::min(procMin_[k], b[k] - R);
            procMax_[k] = std::max(procMax_[k], b[k] + R);
        }
    }
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::overlapMeshAdapter::overlapMeshAdapter
(
    const fvMesh& mesh,
    const dictionary& dict
)
:
    overlapMeshAdapter(mesh, readSettings(dict))
{}


Foam::overlapMeshAdapter::overlapMeshAdapter
(
    const fvMesh& mesh,
    const om::MappingSettings& settings
)
:
    mesh_(mesh),
    settings_(settings),
    twoD_(false),
    z0_(0),
    z1_(0),
    procMin_(om::Vec3::Zero()),
    procMax_(om::Vec3::Zero()),
    nGrains_(0),
    stamp_(0)
{
    // The adapter checks outside grains itself (globally in parallel)
    settings_.outside = om::OutsideGrainPolicy::Skip;

    const label nD = mesh.nSolutionD();
    if (nD == 2)
    {
        if (mesh.solutionD()[vector::Z] != -1)
        {
            FatalErrorInFunction
                << "2D meshes must lie in the x-y plane (one cell thick in z,"
                << " empty front and back patches); this mesh has solution"
                << " directions " << mesh.solutionD() << exit(FatalError);
        }
        twoD_ = true;
        // Global bounds (polyMesh::bounds() is reduced over processors)
        z0_ = mesh.bounds().min().z();
        z1_ = mesh.bounds().max().z();
    }
    else if (nD != 3)
    {
        FatalErrorInFunction
            << "The mesh is " << nD << "-dimensional; grain mapping needs a"
            << " 2D (one cell thick in z, empty front/back) or 3D mesh."
            << exit(FatalError);
    }

    try
    {
        om::MeshView view;
        buildMeshView(view);
        cellMesh_.reset(new om::CellMesh(std::move(view)));
        mapper_.reset(new om::OverlapMapper(*cellMesh_, settings_));
    }
    catch (const std::exception& err)
    {
        FatalErrorInFunction
            << "overlapMapping rejected the mesh or the settings: "
            << err.what() << exit(FatalError);
    }

    visited_.assign(mesh.nCells(), 0u);
    if (Pstream::parRun())
    {
        findProcCells();
    }
    phi_.assign(mesh.nCells(), 0.0);
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

namespace
{
    //- A dimensionless, zeroGradient cell field of the current time
    Foam::tmp<Foam::volScalarField> newDimlessField
    (
        const Foam::fvMesh& mesh,
        const Foam::word& name
    )
    {
        using namespace Foam;
        return tmp<volScalarField>
        (
            new volScalarField
            (
                IOobject
                (
                    name, mesh.time().timeName(), mesh,
                    IOobject::NO_READ, IOobject::NO_WRITE
                ),
                mesh,
                dimensionedScalar(dimless, Zero),
                zeroGradientFvPatchScalarField::typeName
            )
        );
    }
}


void Foam::overlapMeshAdapter::solidFraction(volScalarField& phi) const
{
    scalarField& f = phi.primitiveFieldRef();
    forAll(f, c)
    {
        f[c] = phi_[c];
    }
    phi.correctBoundaryConditions();
}


Foam::tmp<Foam::volScalarField> Foam::overlapMeshAdapter::solidFraction
(
    const word& name
) const
{
    tmp<volScalarField> tphi(newDimlessField(mesh_, name));
    solidFraction(tphi.ref());
    return tphi;
}


void Foam::overlapMeshAdapter::voidFraction(volScalarField& eps) const
{
    scalarField& f = eps.primitiveFieldRef();
    forAll(f, c)
    {
        f[c] = max(1 - phi_[c], settings_.epsMin);
    }
    eps.correctBoundaryConditions();
}


Foam::tmp<Foam::volScalarField> Foam::overlapMeshAdapter::voidFraction
(
    const word& name
) const
{
    tmp<volScalarField> teps(newDimlessField(mesh_, name));
    voidFraction(teps.ref());
    return teps;
}


void Foam::overlapMeshAdapter::solidVelocity
(
    const UList<vector>& v,
    volVectorField& phiV
) const
{
    if (v.size() != nGrains_)
    {
        FatalErrorInFunction
            << "Got " << v.size() << " grain velocities for " << nGrains_
            << " mapped grains" << exit(FatalError);
    }
    vectorField& f = phiV.primitiveFieldRef();
    f = Zero;
    for (std::size_t e = 0; e < entryCell_.size(); ++e)
    {
        f[entryCell_[e]] += entryVolume_[e]*v[entryGrain_[e]];
    }
    f /= mesh_.V();
    phiV.correctBoundaryConditions();
}


void Foam::overlapMeshAdapter::spreadDensity
(
    const UList<vector>& F,
    volVectorField& fd
) const
{
    if (F.size() != nGrains_)
    {
        FatalErrorInFunction
            << "Got " << F.size() << " grain values for " << nGrains_
            << " mapped grains" << exit(FatalError);
    }
    vectorField& f = fd.primitiveFieldRef();
    f = Zero;
    for (std::size_t e = 0; e < entryCell_.size(); ++e)
    {
        const label g = entryGrain_[e];
        f[entryCell_[e]] += (entryVolume_[e]/mappedVolume_[g])*F[g];
    }
    f /= mesh_.V();
    fd.correctBoundaryConditions();
}


namespace
{

template<class Type, class FieldType>
void gatherImpl
(
    const Foam::overlapMeshAdapter& a,
    const FieldType& field,
    Foam::List<Type>& out
)
{
    using namespace Foam;
    out.setSize(a.nGrains());
    out = Zero;
    const Field<Type>& f = field.primitiveField();
    const auto& eg = a.entryGrain();
    const auto& ec = a.entryCell();
    const auto& ev = a.entryVolume();
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        out[eg[e]] += ev[e]*f[ec[e]];
    }
    if (Pstream::parRun())
    {
        // (the components of each grain's value, grain-major)
        const int nc = pTraits<Type>::nComponents;
        std::vector<double> sums(std::size_t(out.size())*nc);
        forAll(out, g)
        {
            for (int k = 0; k < nc; ++k)
            {
                sums[g*nc + k] = component(out[g], k);
            }
        }
        a.sumOverRanks(sums, nc);
        forAll(out, g)
        {
            for (int k = 0; k < nc; ++k)
            {
                setComponent(out[g], k) = sums[g*nc + k];
            }
        }
    }
    const auto& W = a.grainMappedVolume();
    forAll(out, g)
    {
        out[g] = W[g] > 0 ? out[g]/W[g] : Type(Zero);
    }
}

}


void Foam::overlapMeshAdapter::gather
(
    const volVectorField& a,
    List<vector>& ag
) const
{
    gatherImpl<vector>(*this, a, ag);
}


void Foam::overlapMeshAdapter::gather
(
    const volScalarField& a,
    List<scalar>& ag
) const
{
    gatherImpl<scalar>(*this, a, ag);
}


// ************************************************************************* //
