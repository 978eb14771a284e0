/*---------------------------------------------------------------------------*\
  nscdFoam: overlapMeshAdapter (see overlapMeshAdapter.H)
\*---------------------------------------------------------------------------*/

#include "overlapMeshAdapter.H"
#include "grainDictionaryTools.H"

#include "processorPolyPatch.H"
#include "zeroGradientFvPatchFields.H"
#include "Pstream.H"
#include "ops.H"

#include <algorithm>
#include <cmath>
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


void Foam::overlapMeshAdapter::mapHalo
(
    label g,
    const om::Vec3& c,
    double r
)
{
    // Quick reject: the grain misses every processor-boundary cell
    const int nd = twoD_ ? 2 : 3;
    for (int k = 0; k < nd; ++k)
    {
        if (c[k] + r < procMin_[k] || c[k] - r > procMax_[k])
        {
            return;
        }
    }

    const om::CellMesh& m = *cellMesh_;
    if (++stamp_ == 0)
    {
        std::fill(visited_.begin(), visited_.end(), 0u);
        stamp_ = 1;
    }
    auto near = [&](om::label j)
    {
        const om::Vec3& bc = m.boundCentre(j);
        const double R = m.boundRadius(j) + r;
        double d2 = (bc[0] - c[0])*(bc[0] - c[0]) + (bc[1] - c[1])*(bc[1] - c[1]);
        if (!twoD_)
        {
            d2 += (bc[2] - c[2])*(bc[2] - c[2]);
        }
        return d2 < R*R;
    };

    // Seeds: processor-boundary cells near the grain; then breadth-first
    // through face neighbours while the overlap is non-zero (as the library)
    std::vector<om::label> queue;
    for (const om::label j : procCells_)
    {
        if (near(j))
        {
            visited_[j] = stamp_;
            queue.push_back(j);
        }
    }
    const double depth = m.depth();
    const om::Vec2 c2(c[0], c[1]);
    std::size_t head = 0;
    while (head < queue.size())
    {
        const om::label k = queue[head++];
        double vol = 0;
        if (twoD_)
        {
            if (m.convex(k) && m.outsideDistance2D(k, c[0], c[1]) >= r)
            {
                continue;
            }
            vol = om::discPolygonMoments
            (
                c2, r, m.polygon(k), m.polygonSize(k)
            ).area*depth;
        }
        else
        {
            vol = om::sphereCellOverlap(m, k, c, r, false).volume;
        }
        if (!(vol > 0.0))
        {
            continue;
        }
        entryGrain_.push_back(g);
        entryCell_.push_back(k);
        entryVolume_.push_back(vol);
        for (const om::label* nb = m.neighboursBegin(k); nb != m.neighboursEnd(k); ++nb)
        {
            if (visited_[*nb] != stamp_)
            {
                visited_[*nb] = stamp_;
                if (near(*nb))
                {
                    queue.push_back(*nb);
                }
            }
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

void Foam::overlapMeshAdapter::map
(
    const om::Vec3* centres,
    const double* radii,
    label n
)
{
    nGrains_ = n;
    entryGrain_.clear();
    entryCell_.clear();
    entryVolume_.clear();

    const double k = settings_.effectiveDiameterFactor;
    const bool pcm = settings_.method == om::MappingMethod::ParticleCentroid;
    const double zMid = 0.5*(z0_ + z1_);

    // Radii must be valid everywhere (the library checks only mapped grains)
    for (label g = 0; g < n; ++g)
    {
        if (!(radii[g] > 0) || !std::isfinite(radii[g]))
        {
            FatalErrorInFunction
                << "Grain " << g << " has a non-positive or non-finite radius "
                << radii[g] << exit(FatalError);
        }
    }

    // Owner rank of every grain: the lowest rank whose sub-mesh holds its
    // centre (serial: this rank)
    labelList owner(n, labelMax);
    if (Pstream::parRun())
    {
        const label me = Pstream::myProcNo();
        for (label g = 0; g < n; ++g)
        {
            om::Vec3 x(centres[g]);
            if (twoD_)
            {
                x[2] = zMid;
            }
            if (cellMesh_->findCell(x) >= 0)
            {
                owner[g] = me;
            }
        }
        Pstream::listCombineGather(owner, minEqOp<label>());
        Pstream::listCombineScatter(owner);
    }
    else
    {
        owner = Pstream::myProcNo();
    }

    // Owned grains: the library
    std::vector<label> owned;
    owned.reserve(n);
    centres_.clear();
    radii_.clear();
    for (label g = 0; g < n; ++g)
    {
        if (owner[g] == Pstream::myProcNo())
        {
            owned.push_back(g);
            centres_.push_back(centres[g]);
            if (twoD_)
            {
                centres_.back()[2] = zMid;   // nscd discs lie at z = 0
            }
            radii_.push_back(radii[g]);
        }
    }
    try
    {
        mapper_->map(centres_, radii_);
    }
    catch (const std::exception& err)
    {
        FatalErrorInFunction
            << "overlapMapping: " << err.what() << exit(FatalError);
    }
    const std::vector<om::label>& gc = mapper_->grainCell();
    for (std::size_t i = 0; i < owned.size(); ++i)
    {
        if (gc[i] < 0)
        {
            owner[owned[i]] = labelMax;   // reported below
        }
    }
    const std::size_t ne = mapper_->nEntries();
    entryGrain_.reserve(ne);
    for (std::size_t e = 0; e < ne; ++e)
    {
        entryGrain_.push_back(owned[mapper_->entryGrain()[e]]);
        entryCell_.push_back(mapper_->entryCell()[e]);
        entryVolume_.push_back(mapper_->entryVolume()[e]);
    }

    // Grains outside the (global) mesh
    for (label g = 0; g < n; ++g)
    {
        if (owner[g] == labelMax)
        {
            const om::Vec3& x = centres[g];
            FatalErrorInFunction
                << "Grain " << g << " at (" << x[0] << ' ' << x[1] << ' '
                << (twoD_ ? zMid : x[2]) << ") (radius " << radii[g]
                << ") has its centre outside the mesh " << mesh_.bounds()
                << nl << "    Fix: move the grain inside the domain (check"
                << " the grain state and the mesh: grainDeposit writes grains"
                << " inside the mesh; a grain may also have escaped through a"
                << " gap between wall patches)" << exit(FatalError);
        }
    }

    // Grains straddling a processor boundary from another rank
    if (Pstream::parRun() && !pcm)
    {
        for (label g = 0; g < n; ++g)
        {
            if (owner[g] != Pstream::myProcNo())
            {
                mapHalo(g, centres[g], k*radii[g]);
            }
        }
    }

    // Grain volumes
    grainVolume_.resize(n);
    for (label g = 0; g < n; ++g)
    {
        const double r = k*radii[g];
        grainVolume_[g] = twoD_
            ? om::pi*r*r*cellMesh_->depth()
            : om::sphereVolume(r);
    }

    finishMap();
}


void Foam::overlapMeshAdapter::finishMap()
{
    // W_g summed over ranks
    mappedVolume_.assign(nGrains_, 0.0);
    for (std::size_t e = 0; e < entryCell_.size(); ++e)
    {
        mappedVolume_[entryGrain_[e]] += entryVolume_[e];
    }
    if (Pstream::parRun())
    {
        List<scalar> W(nGrains_);
        std::copy(mappedVolume_.begin(), mappedVolume_.end(), W.begin());
        Pstream::listCombineGather(W, plusEqOp<scalar>());
        Pstream::listCombineScatter(W);
        std::copy(W.begin(), W.end(), mappedVolume_.begin());
    }

    // phi_c = sum_g V_gc / V_c
    phi_.assign(mesh_.nCells(), 0.0);
    for (std::size_t e = 0; e < entryCell_.size(); ++e)
    {
        phi_[entryCell_[e]] += entryVolume_[e];
    }
    const scalarField& V = mesh_.V();
    forAll(V, c)
    {
        phi_[c] /= V[c];
    }
}


void Foam::overlapMeshAdapter::map(const nscd::System& grains)
{
    const std::vector<nscd::Vec3>& x = grains.positions();
    const std::vector<double>& r = grains.radii();
    std::vector<om::Vec3> c(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        c[i] = om::Vec3(x[i].x(), x[i].y(), x[i].z());
    }
    map(c.data(), r.data(), label(x.size()));
}


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
        Pstream::listCombineGather(out, plusEqOp<Type>());
        Pstream::listCombineScatter(out);
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
