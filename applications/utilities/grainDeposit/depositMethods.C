// SPDX-License-Identifier: GPL-3.0-or-later
#include "depositMethods.H"
#include "rainDeposit.H"
#include "grainDictionaryTools.H"
#include "cellZone.H"
#include "mathematicalConstants.H"
#include "boundaryDistance.H"

#include <cmath>
#include <utility>
#include <random>
#include <algorithm>

using namespace Foam;

namespace
{

//- A region of the mesh to fill with grains: its bounds [m] and, for method
//  cellZone, the cells of the zone (empty for method box)
struct depositRegion
{
    vector lo, hi;
    labelHashSet zoneCells;
};


//- Index range [first, last) of the lattice nodes lo + (i + 1/2) spacing,
//  i < n, that lie within [bMin, bMax] (the mesh bounds): the nodes outside
//  cannot be in the mesh, so they are not tried (a box given in mm on a mesh
//  in m would otherwise try ~1e8 nodes)
std::pair<long, long> nodeRange
(
    double lo, double n, double spacing, double bMin, double bMax
)
{
    const double a = std::floor((bMin - lo)/spacing - 0.5);
    const double b = std::ceil((bMax - lo)/spacing - 0.5) + 1;
    return {long(std::max(0.0, a)), long(std::max(0.0, std::min(n, b)))};
}

//- Loose jittered lattice over [lo, hi] [m], nodes in fill order (bottom
//  first along up = -gravity), filtered by accept(point); only the nodes
//  within the mesh bounds are tried (the others are not in the mesh).
//  When up is along a coordinate axis the lattice is walked layer by layer
//  from the bottom and the walk stops at the `needed`-th node, so the cost
//  follows the grains asked for, not the region's size over d^3 (one 10 um
//  grain in a 3 cm box: 1e10 nodes, 7 GB and no end before).  The nodes
//  returned are the first ones of the full ordered lattice.
template<class Accept>
std::vector<nscd::Vec3> latticeNodes
(
    const vector& lo, const vector& hi, double spacing, int dim,
    const vector& up, const boundBox& meshBounds, const label needed,
    Accept accept
)
{
    std::vector<nscd::Vec3> nodes;
    const double nx = std::floor((hi.x() - lo.x())/spacing);
    const double ny = std::floor((hi.y() - lo.y())/spacing);
    const double nz = dim == 3 ? std::floor((hi.z() - lo.z())/spacing) : 1;
    const std::pair<long, long> range[3] =
    {
        nodeRange
        (
            lo.x(), nx, spacing, meshBounds.min().x(), meshBounds.max().x()
        ),
        nodeRange
        (
            lo.y(), ny, spacing, meshBounds.min().y(), meshBounds.max().y()
        ),
        dim == 3
      ? nodeRange
        (
            lo.z(), nz, spacing, meshBounds.min().z(), meshBounds.max().z()
        )
      : std::pair<long, long>(0, 1)
    };
    auto tryNode = [&](const long i, const long j, const long k)
    {
        const vector p
        (
            lo.x() + (i + 0.5)*spacing,
            lo.y() + (j + 0.5)*spacing,
            dim == 3 ? lo.z() + (k + 0.5)*spacing : 0.5*(lo.z() + hi.z())
        );
        if (accept(p))
        {
            nodes.emplace_back(p.x(), p.y(), p.z());
        }
    };

    // up along axis a (the other components zero): layers of constant
    // index along a, bottom first; inside a layer the order of the full
    // walk below (z outer, then y, then x)
    label axis = -1;
    for (label a = 0; a < 3; ++a)
    {
        if (up[a] != 0 && up[(a + 1) % 3] == 0 && up[(a + 2) % 3] == 0)
        {
            axis = a;
        }
    }
    if (axis >= 0 && !(dim == 2 && axis == 2))
    {
        // the two other axes, outer first (z before y before x)
        const label outer = axis == 2 ? 1 : 2;
        const label inner = axis == 0 ? 1 : 0;
        const long first = range[axis].first, last = range[axis].second;
        for (long n = 0; n < last - first; ++n)
        {
            const long l = up[axis] > 0 ? first + n : last - 1 - n;
            for (long o = range[outer].first; o < range[outer].second; ++o)
            for (long m = range[inner].first; m < range[inner].second; ++m)
            {
                long idx[3];
                idx[axis] = l;
                idx[outer] = o;
                idx[inner] = m;
                tryNode(idx[0], idx[1], idx[2]);
                if (label(nodes.size()) >= needed)
                {
                    return nodes;
                }
            }
        }
        return nodes;
    }

    // general gravity direction: the whole lattice, sorted along up
    for (long k = range[2].first; k < range[2].second; ++k)
    for (long j = range[1].first; j < range[1].second; ++j)
    for (long i = range[0].first; i < range[0].second; ++i)
    {
        tryNode(i, j, k);
    }
    const nscd::Vec3 u(up.x(), up.y(), up.z());
    std::stable_sort
    (
        nodes.begin(), nodes.end(),
        [&u](const nscd::Vec3& a, const nscd::Vec3& b)
        {
            return a.dot(u) < b.dot(u) - 1e-12;
        }
    );
    return nodes;
}


//- Method replicate: the copies of a settled column (replicateColumn.H)
//  across meshBounds, with their contact impulses as the settling's seed.
//  Logs the number of grains and impulses.  Errors: those of
//  replicateColumn (FatalIOError naming the replicate sub-dictionary).
depositedGrains replicatedGrains
(
    const IOdictionary& depositDict,
    const fileName& casePath,
    const boundBox& meshBounds,
    const label dim
)
{
    depositedGrains out;
    replicatedColumn rc =
        replicateColumn(depositDict, casePath, meshBounds, dim);
    out.specs = std::move(rc.grains);
    out.seedContacts = std::move(rc.contacts);
    out.seedDt = rc.dt;
    Info<< "Replicated the column: " << out.specs.size() << " grains, "
        << out.seedContacts.size() << " contact impulses ("
        << rc.sideContacts << " on its side walls, whose friction, "
        << rc.sideFriction << " of their normal impulse, is not copied)"
        << endl;
    return out;
}


//- Method list: the grains (x y z d) of `grains` [m]; z is dropped in 2D.
//  Error: FatalIOError for a diameter <= 0.
std::vector<grainSpec> listedGrains
(
    const IOdictionary& depositDict,
    const label dim
)
{
    std::vector<grainSpec> specs;
    const List<FixedList<scalar, 4>> list
    (
        depositDict.get<List<FixedList<scalar, 4>>>("grains")
    );
    for (const auto& g : list)
    {
        if (!(g[3] > 0))
        {
            FatalIOErrorInFunction(depositDict)
                << "Grain at (" << g[0] << ' ' << g[1] << ' ' << g[2]
                << ") in 'grains' of " << depositDict.name()
                << " has diameter " << g[3] << " <= 0."
                << " Fix: give a positive diameter." << exit(FatalIOError);
        }
        specs.push_back({nscd::Vec3(g[0], g[1], dim == 3 ? g[2] : 0), g[3]});
    }
    return specs;
}


//- Region of method box (sub-dictionary box { min; max; }) or cellZone (the
//  bounding box [m] of the zone's points, and its cells); 2D: z spans the
//  mesh depth.  Errors: FatalIOError for an unknown keyword of box or an
//  unknown cellZone (listing the zones).
depositRegion readRegion
(
    const IOdictionary& depositDict,
    const word& method,
    const fvMesh& mesh,
    const label dim
)
{
    depositRegion region;
    vector& lo = region.lo;
    vector& hi = region.hi;
    if (method == "box")
    {
        const dictionary& b = depositDict.subDict("box");
        grainTools::checkKeywords(b, {"min", "max"});
        lo = b.get<vector>("min");
        hi = b.get<vector>("max");
        for (direction c = 0; c < dim; ++c)
        {
            if (!(hi[c] > lo[c]))
            {
                FatalIOErrorInFunction(b)
                    << "box { min " << lo << "; max " << hi << "; } in "
                    << depositDict.name() << ": max."
                    << vector::componentNames[c] << " is not above min."
                    << vector::componentNames[c]
                    << " (the box is empty)." << nl << "    Fix: give the"
                    << " lower corner as min and the upper corner as max"
                    << (hi[c] < lo[c] ? " (swap them)." : ".")
                    << exit(FatalIOError);
            }
        }
    }
    else
    {
        const word zoneName = depositDict.get<word>("cellZone");
        const label zonei = mesh.cellZones().findZoneID(zoneName);
        if (zonei < 0)
        {
            FatalIOErrorInFunction(depositDict)
                << "cellZone " << zoneName << " not found. Zones: "
                << flatOutput(mesh.cellZones().names()) << nl
                << "    Fix: create it with topoSet/setsToZones"
                << exit(FatalIOError);
        }
        const label nZoneCells =
            returnReduce(mesh.cellZones()[zonei].size(), sumOp<label>());
        if (nZoneCells == 0)
        {
            FatalIOErrorInFunction(depositDict)
                << "cellZone " << zoneName << " of " << depositDict.name()
                << " holds no cells, so no grain can be placed in it." << nl
                << "    Fix: check the selection that made it (topoSet,"
                << " setsToZones) against the mesh, or use method box."
                << exit(FatalIOError);
        }
        region.zoneCells.insert(mesh.cellZones()[zonei]);
        boundBox bb(mesh.points(), false);
        bb = boundBox::invertedBox;
        for (const label celli : mesh.cellZones()[zonei])
        {
            for (const label pointi : mesh.cellPoints()[celli])
            {
                bb.add(mesh.points()[pointi]);
            }
        }
        lo = bb.min();
        hi = bb.max();
    }
    if (dim == 2)
    {
        lo.z() = mesh.bounds().min().z();
        hi.z() = mesh.bounds().max().z();
    }
    return region;
}


//- The region [lo, hi] against the mesh bounds mb (x, y; and z in 3D),
//  checked before any lattice node is searched (a box in mm on a mesh in m:
//  say so at once instead of searching ~1e8 nodes).  Logs when the region
//  extends beyond mb.  Error: FatalIOError when it does not intersect mb.
void checkRegionInMesh
(
    const IOdictionary& depositDict,
    const vector& lo,
    const vector& hi,
    const boundBox& mb,
    const label dim
)
{
    bool disjoint = false, clipped = false;
    for (direction c = 0; c < (dim == 3 ? 3 : 2); ++c)
    {
        disjoint = disjoint || hi[c] < mb.min()[c] || lo[c] > mb.max()[c];
        clipped = clipped || lo[c] < mb.min()[c] || hi[c] > mb.max()[c];
    }
    if (disjoint)
    {
        FatalIOErrorInFunction(depositDict)
            << "The region " << lo << " - " << hi << " of "
            << depositDict.name() << " does not intersect the mesh"
            << " bounds " << mb << "." << nl
            << "    Fix: give the region in the mesh's units and"
            << " coordinates (a box in mm on a mesh in m?)."
            << exit(FatalIOError);
    }
    if (clipped)
    {
        Info<< "grainDeposit: the region " << lo << " - " << hi
            << " extends beyond the mesh bounds " << mb
            << "; grains are placed in their intersection" << nl;
    }
}


//- Number of grains to place in the region [lo, hi]: `number`, or else
//  solidFraction x region volume [m^3] (2D: area [m^2]) / mean grain volume
//  (diameters uniform in [dMin, lambda dMin], dMin [m]).  Error:
//  FatalIOError when neither is given or solidFraction is not positive.
label grainNumber
(
    const IOdictionary& depositDict,
    const vector& lo,
    const vector& hi,
    const label dim,
    const scalar dMin,
    const scalar lambda
)
{
    const scalar meanVolume = dim == 2
      ? constant::mathematical::pi/4*sqr(dMin)*(1 + lambda + sqr(lambda))/3
      : constant::mathematical::pi/6*pow3(dMin)
       *(1 + lambda)*(1 + sqr(lambda))/4;
    label number = 0;
    if (depositDict.found("number"))
    {
        number = depositDict.get<label>("number");
        if (number < 1)
        {
            FatalIOErrorInFunction(depositDict)
                << "number " << number << " in " << depositDict.name()
                << ": grainDeposit places at least one grain." << nl
                << "    Fix: give number >= 1 (a case without grains needs"
                << " no grainDeposit)."
                << exit(FatalIOError);
        }
    }
    else
    {
        const scalar frac =
            grainTools::getPositive(depositDict, "solidFraction");
        scalar regionVolume = (hi.x() - lo.x())*(hi.y() - lo.y());
        if (dim == 3) regionVolume *= hi.z() - lo.z();
        number = label(frac*regionVolume/meanVolume);
        if (number < 1)
        {
            FatalIOErrorInFunction(depositDict)
                << "solidFraction " << frac << " of the region "
                << lo << " - " << hi << " in " << depositDict.name()
                << " gives " << number << " grains of dMin " << dMin
                << " m." << nl << "    Fix: enlarge the region, raise"
                << " solidFraction or give number." << exit(FatalIOError);
        }
    }
    return number;
}


//- dMin [m] (> 0) and sizeRatio (d_max/d_min, >= 1, default 1) of
//  depositDict.  Errors: FatalIOError for a value out of range.
std::pair<scalar, scalar> grainSizes(const IOdictionary& depositDict)
{
    const scalar dMin = grainTools::getPositive(depositDict, "dMin");
    const scalar lambda = depositDict.getOrDefault<scalar>("sizeRatio", 1);
    if (lambda < 1)
    {
        FatalIOErrorInFunction(depositDict)
            << "sizeRatio (d_max/d_min) must be >= 1, got " << lambda
            << exit(FatalIOError);
    }
    return {dMin, lambda};
}


//- Methods box and cellZone: polydisperse grains (diameters uniform in
//  [dMin, sizeRatio dMin] [m], random with `seed`) on the nodes of a loose
//  jittered lattice (spacing 1.1 d_max) in the region, filled bottom first
//  along -gravity.  Errors (FatalIOError): dMin not positive, sizeRatio < 1,
//  those of readRegion, checkRegionInMesh and grainNumber, and more grains
//  asked for than the lattice holds.
std::vector<grainSpec> latticeGrains
(
    const IOdictionary& depositDict,
    const word& method,
    const fvMesh& mesh,
    const nscd::System& system,
    const label dim
)
{
    std::vector<grainSpec> specs;
    const std::pair<scalar, scalar> sizes = grainSizes(depositDict);
    const scalar dMin = sizes.first, lambda = sizes.second;
    const scalar dMax = lambda*dMin;
    const label seed = depositDict.getOrDefault<label>("seed", 1);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0, 1);

    const depositRegion region = readRegion(depositDict, method, mesh, dim);
    const vector& lo = region.lo;
    const vector& hi = region.hi;
    const labelHashSet& zoneCells = region.zoneCells;

    // loose lattice: spacing 1.1 d_max, jitter within the free space
    const scalar spacing = 1.1*dMax;
    const vector gdir
    (
        -system.gravity().x(),
        -system.gravity().y(),
        -system.gravity().z()
    );
    const scalar zMid = 0.5*(mesh.bounds().min().z() + mesh.bounds().max().z());
    // a node is taken when the largest grain centred on it clears the
    // boundary; the jittered grain is checked again below
    const boundaryDistance wallDistance(mesh);
    const scalar tol = 1e-9*spacing;
    auto accept = [&](const vector& p) -> bool
    {
        const vector pm(p.x(), p.y(), dim == 2 ? zMid : p.z());
        const label celli = mesh.findCell(pm);
        if (celli < 0) return false;
        if (method == "cellZone" && !zoneCells.found(celli)) return false;
        return wallDistance(pm, spacing) >= 0.5*dMax - tol;
    };
    const boundBox& mb = mesh.bounds();
    checkRegionInMesh(depositDict, lo, hi, mb, dim);
    const label number = grainNumber(depositDict, lo, hi, dim, dMin, lambda);
    const std::vector<nscd::Vec3> nodes =
        latticeNodes(lo, hi, spacing, dim, gdir, mb, number, accept);
    if (number < 1 || number > label(nodes.size()))
    {
        FatalIOErrorInFunction(depositDict)
            << "Cannot place " << number << " grains: the region of "
            << depositDict.name() << " holds " << nodes.size()
            << " grains on the loose insertion lattice (spacing "
            << spacing << " m)." << nl
            << "    Fix: enlarge the region (it may extend above the"
            << " final bed, grains settle) or ask for fewer grains."
            << exit(FatalIOError);
    }
    const scalar jitter = 0.5*(spacing - dMax);
    for (label n = 0; n < number; ++n)
    {
        const scalar d = dMin + (dMax - dMin)*uni(rng);
        nscd::Vec3 x = nodes[n];
        x.x() += jitter*(2*uni(rng) - 1);
        x.y() += jitter*(2*uni(rng) - 1);
        if (dim == 3) x.z() += jitter*(2*uni(rng) - 1);
        else x.z() = 0;
        // a jitter towards a slanted wall may bring the grain across it
        // (never along the lattice: the node then lies half a spacing, the
        // largest grain's radius plus the jitter, from the wall): halve it
        // until the grain clears the boundary (the node itself does)
        const nscd::Vec3& node = nodes[n];
        for (int halve = 0; halve < 4; ++halve)
        {
            const point c(x.x(), x.y(), dim == 2 ? zMid : x.z());
            if (wallDistance(c, spacing) >= 0.5*d - tol) break;
            x = halve == 3 ? node : nscd::Vec3(0.5*(x + node));
            if (dim == 2) x.z() = 0;
        }
        specs.push_back({x, d});
    }
    return specs;
}


//- Method rain (2D): the grains of latticeGrains' keywords (box, number or
//  solidFraction, dMin, sizeRatio, seed) laid one by one over the box's
//  floor between its sides (rainDeposit.H).  Errors (FatalIOError): a 3D
//  case, gravity not along -y, those of latticeGrains' keywords, and a
//  deposit that rises above the box.
std::vector<grainSpec> rainGrains
(
    const IOdictionary& depositDict,
    const fvMesh& mesh,
    const nscd::System& system,
    const label dim
)
{
    if (dim != 2)
    {
        FatalIOErrorInFunction(depositDict)
            << "method rain in " << depositDict.name() << " lays discs: it"
            << " needs a 2D case (one cell and empty patches across z)." << nl
            << "    Fix: use method box or cellZone with settle in 3D."
            << exit(FatalIOError);
    }
    const nscd::Vec3& g = system.gravity();
    if (!(g.y() < 0) || std::abs(g.x()) > 1e-12*g.norm())
    {
        FatalIOErrorInFunction(depositDict)
            << "method rain in " << depositDict.name() << " drops the grains"
            << " along -y, but constant/g is (" << g.x() << ' ' << g.y()
            << ' ' << g.z() << ")." << nl
            << "    Fix: set gravity along -y, or use method box with settle."
            << exit(FatalIOError);
    }
    const std::pair<scalar, scalar> sizes = grainSizes(depositDict);
    const scalar dMin = sizes.first, lambda = sizes.second;
    const label seed = depositDict.getOrDefault<label>("seed", 1);
    const depositRegion region = readRegion(depositDict, "box", mesh, dim);
    checkRegionInMesh(depositDict, region.lo, region.hi, mesh.bounds(), dim);
    if (region.hi.x() - region.lo.x() < lambda*dMin)
    {
        FatalIOErrorInFunction(depositDict)
            << "The box of " << depositDict.name() << " is "
            << region.hi.x() - region.lo.x() << " m wide, less than the"
            << " largest grain (" << lambda*dMin << " m)."
            << exit(FatalIOError);
    }
    const label number =
        grainNumber(depositDict, region.lo, region.hi, dim, dMin, lambda);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uni(0, 1);
    std::vector<double> diameters(std::max(label(0), number));
    for (double& d : diameters) d = dMin*(1 + (lambda - 1)*uni(rng));
    std::vector<grainSpec> specs = rainDeposit
    (
        region.lo.x(), region.hi.x(), region.lo.y(), diameters, rng
    );
    scalar top = region.lo.y();
    for (const grainSpec& s : specs) top = max(top, s.x.y() + 0.5*s.d);
    if (top > region.hi.y())
    {
        FatalIOErrorInFunction(depositDict)
            << "The rain deposit of " << number << " grains rises to y = "
            << top << " m, above the box of " << depositDict.name()
            << " (max y " << region.hi.y() << " m)." << nl
            << "    Fix: ask for fewer grains or raise the box's max."
            << exit(FatalIOError);
    }
    Info<< "Rain deposit: " << specs.size() << " grains, top at y = " << top
        << " m" << endl;
    return specs;
}

} // End anonymous namespace


// * * * * * * * * * * * * * * * Global Functions  * * * * * * * * * * * * * //

Foam::depositedGrains Foam::depositGrains
(
    const IOdictionary& depositDict,
    const word& method,
    const fvMesh& mesh,
    const grainCloud& settling
)
{
    const label dim = settling.dimension();
    depositedGrains dep;
    if (method == "replicate")
    {
        dep = replicatedGrains
        (
            depositDict, mesh.time().path(), mesh.bounds(), dim
        );
    }
    else if (method == "list")
    {
        dep.specs = listedGrains(depositDict, dim);
    }
    else if (method == "rain")
    {
        dep.specs = rainGrains(depositDict, mesh, settling.system(), dim);
    }
    else if (method == "box" || method == "cellZone")
    {
        dep.specs =
            latticeGrains(depositDict, method, mesh, settling.system(), dim);
    }
    else
    {
        FatalIOErrorInFunction(depositDict)
            << "Unknown method " << method << " in " << depositDict.name()
            << ". Use box, cellZone, rain, list or replicate."
            << exit(FatalIOError);
    }
    return dep;
}
