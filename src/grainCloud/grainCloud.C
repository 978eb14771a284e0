#include "grainCloud.H"
#include "grainDictionaryTools.H"
#include "uniformDimensionedFields.H"
#include "wallPolyPatch.H"
#include "passiveParticleCloud.H"
#include "IOField.H"
#include "OSspecific.H"
#include "OStringStream.H"

#include <cmath>
#include <algorithm>
#include <utility>

// * * * * * * * * * * * * * * Static Data Members * * * * * * * * * * * * * //

const Foam::word Foam::grainCloud::stateFileName("grainState.h5");
const Foam::word Foam::grainCloud::cloudName("grains");
const Foam::word Foam::grainCloud::registryName("grainCloud");

namespace Foam
{
    defineTypeNameAndDebug(grainCloudReference, 0);
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

namespace
{
    inline nscd::Vec3 toVec3(const Foam::vector& v)
    {
        return nscd::Vec3(v.x(), v.y(), v.z());
    }
    inline Foam::vector toVector(const nscd::Vec3& v)
    {
        return Foam::vector(v.x(), v.y(), v.z());
    }
}


void Foam::grainCloud::readSettings()
{
    grainTools::checkKeywords
    (
        dict_,
        {
            "materials", "wallPatches", "maxDisplacementFraction",
            "contactSolver", "movingWalls", "initialTemperature",
            "wallTemperatures", "gates", "frontRearWalls", "outletPatches"
        }
    );

    maxDisplacementFraction_ =
        grainTools::getPositiveOrDefault(dict_, "maxDisplacementFraction", 0.1);
    if (maxDisplacementFraction_ > 0.5)
    {
        FatalIOErrorInFunction(dict_)
            << "maxDisplacementFraction " << maxDisplacementFraction_
            << " in " << dict_.name() << " is too large: grains could cross"
            << " each other within a sub-step. Use a value <= 0.5 (0.1 is"
            << " the default)." << exit(FatalIOError);
    }

    const dictionary& mats = dict_.subDict("materials");
    if (mats.empty())
    {
        FatalIOErrorInFunction(mats)
            << "No material in " << mats.name()
            << ". Add e.g. glass { density 2500; friction 0.4; }"
            << exit(FatalIOError);
    }
    for (const entry& e : mats)
    {
        if (!e.isDict())
        {
            FatalIOErrorInFunction(mats)
                << "Entry '" << e.keyword() << "' of " << mats.name()
                << " must be a dictionary { density ...; friction ...; }"
                << exit(FatalIOError);
        }
        grainTools::checkKeywords
        (
            e.dict(),
            {
                "density", "friction", "youngModulus", "poissonRatio",
                "conductivity", "heatCapacity"
            }
        );
        const scalar mu = e.dict().get<scalar>("friction");
        if (mu < 0)
        {
            FatalIOErrorInFunction(e.dict())
                << "friction of material " << e.keyword() << " must be >= 0"
                << exit(FatalIOError);
        }
        grainTools::getPositive(e.dict(), "density");
    }
}


namespace
{
// contactSolver.method: the nscd::System::Settings::Method of the name
nscd::System::Settings::Method contactSolverMethod(const Foam::dictionary& cs)
{
    using Method = nscd::System::Settings::Method;
    const Foam::word m(cs.get<Foam::word>("method"));
    if (m == "NLGS") return Method::NLGS;
    if (m == "overRelaxedNLGS") return Method::OverRelaxedNLGS;
    if (m != "APGD")
    {
        FatalIOErrorInFunction(cs)
            << "unknown contactSolver method " << m
            << "; methods: NLGS, overRelaxedNLGS, APGD" << Foam::exit(Foam::FatalIOError);
    }
    return Method::APGD;
}
}


void Foam::grainCloud::applySolverSettings()
{
    nscd::System::Settings& s = system_->settings();
    if (dict_.found("contactSolver"))
    {
        const dictionary& cs = dict_.subDict("contactSolver");
        grainTools::checkKeywords
        (
            cs,
            {
                "tolerance", "maxIterations", "overlapTolerance", "method",
                "relaxation", "maxSubSteps"
            }
        );
        if (cs.found("method"))
        {
            s.method = contactSolverMethod(cs);
        }
        s.relaxation = cs.getOrDefault<scalar>("relaxation", s.relaxation);
        if (!(s.relaxation > 0 && s.relaxation < 2))
        {
            FatalIOErrorInFunction(cs)
                << "relaxation must be in (0, 2), got " << s.relaxation
                << exit(FatalIOError);
        }
        s.tolerance =
            grainTools::getPositiveOrDefault(cs, "tolerance", s.tolerance);
        s.maxIterations = cs.getOrDefault<label>("maxIterations", s.maxIterations);
        s.overlapTolerance =
            grainTools::getPositiveOrDefault
            (
                cs, "overlapTolerance", s.overlapTolerance
            );
        if (s.maxIterations < 1)
        {
            FatalIOErrorInFunction(cs)
                << "maxIterations must be >= 1" << exit(FatalIOError);
        }
        s.maxSubSteps = cs.getOrDefault<label>("maxSubSteps", s.maxSubSteps);
        if (s.maxSubSteps < 1)
        {
            FatalIOErrorInFunction(cs)
                << "maxSubSteps must be >= 1" << exit(FatalIOError);
        }
    }
}


Foam::label Foam::grainCloud::materialId(const word& name) const
{
    const dictionary& mats = dict_.subDict("materials");
    const wordList names(mats.toc());
    label id = 0;
    for (const entry& e : mats)
    {
        if (e.keyword() == name)
        {
            return id;
        }
        ++id;
    }
    FatalIOErrorInFunction(mats)
        << "Unknown material '" << name << "'. Materials defined in "
        << mats.name() << ": " << flatOutput(names) << exit(FatalIOError);
    return -1;
}


namespace
{
    Foam::labelList wallPatchIds(const Foam::fvMesh& mesh, const Foam::dictionary& dict)
    {
        using namespace Foam;
        const polyBoundaryMesh& pbm = mesh.boundaryMesh();
        labelList ids;
        if (dict.found("wallPatches"))
        {
            ids = grainTools::patchIds
            (
                pbm, dict, "wallPatches", "the grains would fall through it"
            );
            if (ids.empty())
            {
                FatalIOErrorInFunction(dict)
                    << "wallPatches " << flatOutput(dict.get<wordRes>("wallPatches"))
                    << " in "
                    << dict.name() << " matches no patch of the mesh. Patches: "
                    << flatOutput(pbm.names()) << exit(FatalIOError);
            }
        }
        else
        {
            DynamicList<label> w;
            forAll(pbm, patchi)
            {
                if (isA<wallPolyPatch>(pbm[patchi]))
                {
                    w.append(patchi);
                }
            }
            ids.transfer(w);
        }
        return ids;
    }
}


namespace
{
    //- The 2D wall segments of a patch of a one-cell-thick mesh: the back-plane
    //  edge of every face, with collinear edges that touch or overlap merged
    //  into one segment (a straight wall is one segment, so no spurious
    //  corner contacts appear where two faces meet).
    std::vector<std::pair<nscd::Vec3, nscd::Vec3>> patchSegments
    (
        const Foam::polyMesh& mesh,
        const Foam::polyPatch& pp,
        const Foam::scalar zMid
    )
    {
        using namespace Foam;
        struct line { nscd::Vec3 o, t; std::vector<std::pair<double, double>> iv; };
        std::vector<line> lines;
        const scalar tol = 1e-9*mag(mesh.bounds().span());

        // back-plane edges of the patch faces, from every rank (the grains
        // see the whole wall on every rank)
        List<List<point>> edges(Pstream::nProcs());
        DynamicList<point> mine;
        for (const face& f : pp)
        {
            DynamicList<nscd::Vec3> back(2);
            for (const label pointi : f)
            {
                const point& p = mesh.points()[pointi];
                if (p.z() < zMid)
                {
                    back.append(nscd::Vec3(p.x(), p.y(), 0));
                }
            }
            if (back.size() != 2)
            {
                FatalErrorInFunction
                    << "Wall face of patch " << pp.name() << " has "
                    << back.size() << " points on the back plane; a 2D"
                    << " mesh must be one cell thick in z with empty"
                    << " front and back patches." << exit(FatalError);
            }
            mine.append(point(back[0].x(), back[0].y(), 0));
            mine.append(point(back[1].x(), back[1].y(), 0));
        }
        edges[Pstream::myProcNo()] = mine;
        Pstream::gatherList(edges);
        Pstream::scatterList(edges);
        for (const List<point>& ed : edges)
        for (label k = 0; k + 1 < ed.size(); k += 2)
        {
            const nscd::Vec3 a(ed[k].x(), ed[k].y(), 0);
            const nscd::Vec3 b(ed[k + 1].x(), ed[k + 1].y(), 0);
            line* found = nullptr;
            for (line& l : lines)
            {
                const nscd::Vec3 da = a - l.o, db = b - l.o;
                if
                (
                    std::abs(da.x()*l.t.y() - da.y()*l.t.x()) < tol
                 && std::abs(db.x()*l.t.y() - db.y()*l.t.x()) < tol
                )
                {
                    found = &l;
                    break;
                }
            }
            if (!found)
            {
                lines.push_back({a, (b - a).normalized(), {}});
                found = &lines.back();
            }
            double sa = (a - found->o).dot(found->t);
            double sb = (b - found->o).dot(found->t);
            if (sa > sb) std::swap(sa, sb);
            found->iv.push_back({sa, sb});
        }
        std::vector<std::pair<nscd::Vec3, nscd::Vec3>> segs;
        for (line& l : lines)
        {
            std::sort(l.iv.begin(), l.iv.end());
            double s0 = l.iv[0].first, s1 = l.iv[0].second;
            for (std::size_t k = 1; k <= l.iv.size(); ++k)
            {
                if (k < l.iv.size() && l.iv[k].first <= s1 + tol)
                {
                    s1 = std::max(s1, l.iv[k].second);
                    continue;
                }
                nscd::Vec3 a = l.o + s0*l.t, b = l.o + s1*l.t;
                if (b.x() < a.x() || (b.x() == a.x() && b.y() < a.y()))
                {
                    std::swap(a, b);
                }
                segs.push_back({a, b});
                if (k < l.iv.size())
                {
                    s0 = l.iv[k].first;
                    s1 = l.iv[k].second;
                }
            }
        }
        // canonical order, independent of the face order and decomposition
        const scalar q = 1e-6*mag(mesh.bounds().span());
        auto key = [q](const nscd::Vec3& v) { return std::llround(v.x()/q)*1000003LL + std::llround(v.y()/q); };
        std::sort
        (
            segs.begin(), segs.end(),
            [&key](const auto& u, const auto& v)
            {
                const long long ku = key(u.first), kv = key(v.first);
                return ku != kv ? ku < kv : key(u.second) < key(v.second);
            }
        );
        return segs;
    }
}


void Foam::grainCloud::computePatchWallIds()
{
    patchWalls_.clear();
    const labelList ids(wallPatchIds(mesh_, dict_));
    label wallId = 0;
    for (const label patchi : ids)
    {
        const polyPatch& pp = mesh_.boundaryMesh()[patchi];
        labelList walls;
        if (dimension_ == 2)
        {
            const label n = patchSegments(mesh_, pp, zMid_).size();
            walls = identity(n, wallId);
            wallId += n;
        }
        else
        {
            walls = labelList(1, wallId++);
        }
        patchWalls_.insert(pp.name(), walls);
    }
}


void Foam::grainCloud::addMeshWalls()
{
    const labelList ids(wallPatchIds(mesh_, dict_));
    for (const label patchi : ids)
    {
        const polyPatch& pp = mesh_.boundaryMesh()[patchi];
        if (dimension_ == 2)
        {
            for (const auto& seg : patchSegments(mesh_, pp, zMid_))
            {
                system_->addSegment(seg.first, seg.second);
            }
        }
        else
        {
            std::vector<nscd::Vec3> vertices;
            std::vector<std::array<int, 3>> triangles;
            const pointField& lp = pp.localPoints();
            vertices.reserve(lp.size());
            for (const point& p : lp)
            {
                vertices.push_back(toVec3(p));
            }
            for (const face& f : pp.localFaces())
            {
                for (label k = 1; k + 1 < f.size(); ++k)
                {
                    triangles.push_back({f[0], f[k], f[k + 1]});
                }
            }
            system_->addTriangulatedSurface(vertices, triangles);
        }
    }
}


void Foam::grainCloud::readMovingWalls()
{
    movingWalls_.clear();
    if (!dict_.found("movingWalls"))
    {
        return;
    }
    const dictionary& mw = dict_.subDict("movingWalls");
    for (const entry& e : mw)
    {
        if (!e.isDict() || !patchWalls_.found(e.keyword()))
        {
            FatalIOErrorInFunction(mw)
                << "movingWalls entry '" << e.keyword() << "' in "
                << mw.name() << " must be a dictionary named after a wall"
                << " patch. Wall patches: " << flatOutput(patchWalls_.sortedToc())
                << exit(FatalIOError);
        }
        const dictionary& d = e.dict();
        grainTools::checkKeywords(d, {"velocity", "startTime", "endTime"});
        movingWall w;
        w.patch = e.keyword();
        w.velocity = d.get<vector>("velocity");
        w.startTime = d.getOrDefault<scalar>("startTime", -GREAT);
        w.endTime = d.getOrDefault<scalar>("endTime", GREAT);
        w.wallIds = patchWalls_[w.patch];
        if (dimension_ == 2 && mag(w.velocity.z()) > 0)
        {
            FatalIOErrorInFunction(d)
                << "velocity of moving wall " << w.patch << " has a z"
                << " component in a 2D case" << exit(FatalIOError);
        }
        movingWalls_.append(w);
    }
}


void Foam::grainCloud::readGates(const label nMeshWalls)
{
    gates_.clear();
    if (dict_.found("gates"))
    {
        const dictionary& gd = dict_.subDict("gates");
        for (const entry& e : gd)
        {
            if (!e.isDict())
            {
                FatalIOErrorInFunction(gd)
                    << "gates entry '" << e.keyword() << "' in " << gd.name()
                    << " must be a dictionary { start (x y z); end (x y z);"
                    << " velocity (u v w); startTime t0; endTime t1; }"
                    << exit(FatalIOError);
            }
            const dictionary& d = e.dict();
            grainTools::checkKeywords
            (
                d, {"start", "end", "velocity", "startTime", "endTime"}
            );
            gate g;
            g.name = e.keyword();
            g.start = d.get<vector>("start");
            g.end = d.get<vector>("end");
            g.velocity = d.get<vector>("velocity");
            g.startTime = d.getOrDefault<scalar>("startTime", -GREAT);
            g.endTime = d.getOrDefault<scalar>("endTime", GREAT);
            g.wallId = nMeshWalls + gates_.size();
            if (dimension_ == 2 && mag(g.velocity.z()) > 0)
            {
                FatalIOErrorInFunction(d)
                    << "velocity of gate " << g.name << " in " << d.name()
                    << " has a z component in a 2D case (x-y plane)"
                    << exit(FatalIOError);
            }
            vector seg(g.end - g.start);
            seg.z() = 0;
            if (mag(seg) < SMALL)
            {
                FatalIOErrorInFunction(d)
                    << "gate " << g.name << " in " << d.name() << ": start "
                    << g.start << " and end " << g.end << " coincide in the"
                    << " x-y plane. Fix: give two distinct points (2D: the"
                    << " segment; 3D: the rectangle's bottom and top edge"
                    << " ends, swept over the mesh depth)." << exit(FatalIOError);
            }
            if (!(g.endTime > g.startTime))
            {
                FatalIOErrorInFunction(d)
                    << "gate " << g.name << " in " << d.name() << ": endTime "
                    << g.endTime << " must be > startTime " << g.startTime
                    << exit(FatalIOError);
            }
            gates_.append(g);
        }
    }

    const label nWalls = system_->nWalls();
    if (nWalls == nMeshWalls + gates_.size() && nWalls > nMeshWalls)
    {
        // state written with the gates (their displacement is restored)
        return;
    }
    if (nWalls != nMeshWalls)
    {
        FatalErrorInFunction
            << "The grain state has " << nWalls << " walls but the wall"
            << " patches give " << nMeshWalls << " and 'gates' "
            << gates_.size() << "." << nl
            << "    The mesh, wallPatches or gates changed since the state"
            << " was written: re-run grainDeposit." << exit(FatalError);
    }
    try
    {
        for (const gate& g : gates_)
        {
            label id = -1;
            if (dimension_ == 2)
            {
                id = system_->addSegment(toSystem(g.start), toSystem(g.end));
            }
            else
            {
                const scalar z0 = mesh_.bounds().min().z();
                const scalar z1 = mesh_.bounds().max().z();
                const std::vector<nscd::Vec3> v
                {
                    nscd::Vec3(g.start.x(), g.start.y(), z0),
                    nscd::Vec3(g.end.x(), g.end.y(), z0),
                    nscd::Vec3(g.end.x(), g.end.y(), z1),
                    nscd::Vec3(g.start.x(), g.start.y(), z1)
                };
                id = system_->addTriangulatedSurface(v, {{0, 1, 2}, {0, 2, 3}});
            }
            if (id != g.wallId)
            {
                FatalErrorInFunction
                    << "gate " << g.name << " got wall id " << id
                    << " instead of " << g.wallId << exit(FatalError);
            }
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Grain system (gates): " << err.what() << exit(FatalError);
    }
}


Foam::vector Foam::grainCloud::gateDisplacement(const label gatei) const
{
    return toVector(system_->wallDisplacement(gates_[gatei].wallId));
}


void Foam::grainCloud::readWallTemperatures()
{
    wallTemperatures_.clear();
    if (!dict_.found("wallTemperatures"))
    {
        return;
    }
    const dictionary& wt = dict_.subDict("wallTemperatures");
    const wordList patches(patchWalls_.sortedToc());
    // every wall patch adiabatic, then the listed ones at their temperature
    // (a patch matched by several entries: the last one wins)
    HashTable<scalar> Tpatch;
    for (const entry& e : wt)
    {
        if (!e.isStream())
        {
            FatalIOErrorInFunction(wt)
                << "wallTemperatures entry '" << e.keyword() << "' in "
                << wt.name() << " must be '<patch or \"regex\"> <T [K]>;'"
                << exit(FatalIOError);
        }
        const scalar T = wt.get<scalar>(e.keyword());
        if (!std::isfinite(T) || T < 0)
        {
            FatalIOErrorInFunction(wt)
                << "wallTemperatures " << e.keyword() << " " << T
                << " in " << wt.name() << ": the temperature must be a"
                << " finite value >= 0 [K]" << exit(FatalIOError);
        }
        const wordRe re(e.keyword());
        bool matched = false;
        for (const word& p : patches)
        {
            if (re.match(p))
            {
                Tpatch.set(p, T);
                matched = true;
            }
        }
        if (!matched)
        {
            FatalIOErrorInFunction(wt)
                << "wallTemperatures entry '" << e.keyword() << "' in "
                << wt.name() << " matches no wall patch. Wall patches: "
                << flatOutput(patches) << exit(FatalIOError);
        }
    }
    try
    {
        for (const word& p : patches)
        {
            for (const label id : patchWalls_[p])
            {
                if (Tpatch.found(p))
                {
                    system_->setWallTemperature(id, Tpatch[p]);
                }
                else
                {
                    system_->setWallAdiabatic(id);
                }
            }
            if (Tpatch.found(p))
            {
                wallTemperatures_.append(std::make_pair(p, Tpatch[p]));
            }
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Grain system: " << err.what() << exit(FatalError);
    }
    for (const auto& pt : wallTemperatures_)
    {
        Info<< "grainCloud: wall patch " << pt.first << " at " << pt.second
            << " K (" << patchWalls_[pt.first].size() << " walls)" << nl;
    }
}


void Foam::grainCloud::readFrontRearWalls()
{
    frontRearWalls_ = dict_.found("frontRearWalls");
    if (!frontRearWalls_)
    {
        // a state written by a run with frontRearWalls keeps the grains'
        // bath exchange (nscd state): switch it off, the dictionary rules
        label n = 0;
        for (std::size_t i = 0; i < system_->size(); ++i)
        {
            if (system_->heatExchange(i).first > 0)
            {
                system_->setHeatExchange(i, 0, 0);
                ++n;
            }
        }
        if (n)
        {
            Info<< "grainCloud: no frontRearWalls in " << dict_.name()
                << ": the bath exchange of " << n << " grains of the state"
                << " is switched off" << nl;
        }
        return;
    }
    const dictionary& fr = dict_.subDict("frontRearWalls");
    grainTools::checkKeywords(fr, {"temperature", "relaxationTime"});
    if (mesh_.nSolutionD() != 2)
    {
        FatalIOErrorInFunction(fr)
            << "frontRearWalls in " << fr.name() << " models the front and"
            << " rear walls of a Hele-Shaw cell in a 2D run, but the mesh"
            << " solves " << mesh_.nSolutionD() << " directions." << nl
            << "    Fix: remove frontRearWalls (a 3D mesh has its walls as"
            << " patches: wallTemperatures)." << exit(FatalIOError);
    }
    frontRearTemperature_ = fr.get<scalar>("temperature");
    frontRearRelaxationTime_ = fr.get<scalar>("relaxationTime");
    if (!(frontRearTemperature_ > 0) || !std::isfinite(frontRearTemperature_))
    {
        FatalIOErrorInFunction(fr)
            << "frontRearWalls temperature " << frontRearTemperature_
            << " in " << fr.name() << ": give the walls' temperature T_w"
            << " [K] > 0." << exit(FatalIOError);
    }
    if
    (
        !(frontRearRelaxationTime_ > 0)
     || !std::isfinite(frontRearRelaxationTime_)
    )
    {
        FatalIOErrorInFunction(fr)
            << "frontRearWalls relaxationTime " << frontRearRelaxationTime_
            << " in " << fr.name() << ": give tau [s] > 0, e.g. (rho c)_bed"
            << " l^2/(12 k_eff) for a gap l (grainCloud.H)."
            << exit(FatalIOError);
    }
    bool heat = false;
    for (int m = 0; m < system_->nMaterials(); ++m)
    {
        heat = heat || system_->material(m).heatCapacity > 0;
    }
    if (!heat)
    {
        FatalIOErrorInFunction(fr)
            << "frontRearWalls in " << fr.name() << " but no material has a"
            << " heatCapacity: no grain temperature is integrated." << nl
            << "    Fix: give the materials heatCapacity (and conductivity),"
            << " or remove frontRearWalls." << exit(FatalIOError);
    }
    Info<< "grainCloud: front and rear walls (Hele-Shaw cell) at "
        << frontRearTemperature_ << " K, grain relaxation time "
        << frontRearRelaxationTime_ << " s" << nl;
}


void Foam::grainCloud::applyFrontRearWalls()
{
    if (!frontRearWalls_)
    {
        return;
    }
    try
    {
        for (std::size_t i = 0; i < system_->size(); ++i)
        {
            const scalar c =
                system_->material(system_->materials()[i]).heatCapacity;
            if (c > 0 && !system_->fixedTemperature(i))
            {
                system_->setHeatExchange
                (
                    i,
                    system_->mass(i)*c/frontRearRelaxationTime_,
                    frontRearTemperature_
                );
            }
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Grain system (frontRearWalls): " << err.what()
            << exit(FatalError);
    }
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

std::vector<nscd::Material> Foam::grainCloud::dictionaryMaterials() const
{
    std::vector<nscd::Material> list;
    for (const entry& e : dict_.subDict("materials"))
    {
        const dictionary& d = e.dict();
        nscd::Material m;
        m.density = d.get<scalar>("density");
        m.friction = d.get<scalar>("friction");
        m.youngModulus = d.getOrDefault<scalar>("youngModulus", 0);
        m.poissonRatio = d.getOrDefault<scalar>("poissonRatio", 0);
        m.conductivity = d.getOrDefault<scalar>("conductivity", 0);
        m.heatCapacity = d.getOrDefault<scalar>("heatCapacity", 0);
        if (m.conductivity > 0 && !(m.youngModulus > 0))
        {
            WarningInFunction
                << "Material " << e.keyword() << " in " << dict_.name()
                << " has conductivity " << m.conductivity << " but no"
                << " youngModulus: contact conduction (thesis eq. 4.2) is"
                << " off for it, the grains exchange heat with the fluid"
                << " only. Give youngModulus (and poissonRatio) to switch"
                << " it on." << endl;
        }
        list.push_back(m);
    }
    return list;
}


void Foam::grainCloud::applyDictionaryMaterials(const fileName& statePath)
{
    // constant/grainProperties is authoritative, as any constant/ property
    // of an OpenFOAM case: a state written by another case (e.g. a deposit
    // copied into each case that starts from it) keeps its grains but takes
    // this case's materials.  Unchanged materials leave a restart exact.
    const std::vector<nscd::Material> list = dictionaryMaterials();
    const dictionary& mats = dict_.subDict("materials");
    if (label(list.size()) != system_->nMaterials())
    {
        FatalIOErrorInFunction(mats)
            << statePath << " holds " << system_->nMaterials()
            << " materials but " << mats.name() << " lists " << list.size()
            << "." << nl << "    Materials are matched by their order"
            << " (id 0, 1, ...): list as many as the state was written with,"
            << " in the same order, or re-run grainDeposit."
            << exit(FatalIOError);
    }
    wordList names(mats.toc());
    for (label id = 0; id < label(list.size()); ++id)
    {
        const nscd::Material& old = system_->material(id);
        const nscd::Material& m = list[id];
        OStringStream changes;
        auto note = [&changes](const char* what, scalar was, scalar now)
        {
            if (was != now)
            {
                changes << ", " << what << " " << was << " -> " << now;
            }
        };
        note("density", old.density, m.density);
        note("friction", old.friction, m.friction);
        note("youngModulus", old.youngModulus, m.youngModulus);
        note("poissonRatio", old.poissonRatio, m.poissonRatio);
        note("conductivity", old.conductivity, m.conductivity);
        note("heatCapacity", old.heatCapacity, m.heatCapacity);
        if (changes.str().empty())
        {
            continue;
        }
        Info<< "grainCloud: material " << names[id] << " (id " << id
            << ") of constant/grainProperties replaces the one in "
            << (statePath.path().name()/statePath.name()).c_str() << ": "
            << changes.str().substr(2).c_str()
            << " (grain masses recomputed)"
            << endl;
        system_->setMaterial(id, m);
    }
}


Foam::grainCloud::grainCloud(const fvMesh& mesh, bool readState)
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
    maxDisplacementFraction_(0.1)
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

    fileName statePath(mesh.time().timePath()/stateFileName);
    if (Pstream::parRun() && !isFile(statePath))
    {
        // decomposed case: every rank reads the undecomposed case's state
        // (grains are held whole on every rank)
        statePath =
            mesh.time().globalPath()/mesh.time().timeName()/stateFileName;
    }
    try
    {
        if (readState)
        {
            // a missing, damaged or bad file: FatalError naming the
            // previous write that holds a state (grainCloudChecks.C)
            system_.reset(new nscd::System(readStateFile(statePath)));
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
            system_.reset(new nscd::System(dimension_));
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
    readWallTemperatures();
    readFrontRearWalls();
    applySolverSettings();
    setHeartbeat();

    // Gravity: the standard constant/g
    uniformDimensionedVectorField g
    (
        IOobject
        (
            "g",
            mesh.time().constant(),
            mesh,
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

    Info<< "grainCloud: " << system_->size() << (dimension_ == 2 ? " discs" : " spheres")
        << ", " << system_->nWalls() << " walls from "
        << patchWalls_.size() << " wall patches, "
        << movingWalls_.size() << " moving, " << gates_.size()
        << " gates" << nl << endl;
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::vector Foam::grainCloud::meshPosition(label i) const
{
    const nscd::Vec3& x = system_->positions()[i];
    return vector(x.x(), x.y(), dimension_ == 2 ? zMid_ : x.z());
}


nscd::Vec3 Foam::grainCloud::toSystem(const vector& p) const
{
    return nscd::Vec3(p.x(), p.y(), dimension_ == 2 ? 0 : p.z());
}


void Foam::grainCloud::checkState() const
{
    const std::vector<double>& r = system_->radii();
    labelList found(system_->size(), 0);
    for (std::size_t i = 0; i < system_->size(); ++i)
    {
        found[i] = mesh_.findCell(meshPosition(i)) >= 0 ? 1 : 0;
    }
    Pstream::listCombineGather(found, maxEqOp<label>());
    Pstream::listCombineScatter(found);
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
    const scalar t0 = mesh_.time().value() - dt;
    for (const movingWall& w : movingWalls_)
    {
        const bool on = (t0 >= w.startTime - SMALL && t0 < w.endTime - SMALL);
        const nscd::Vec3 v = on ? toVec3(w.velocity) : nscd::Vec3::Zero();
        for (const label id : w.wallIds)
        {
            system_->setWallVelocity(id, v);
        }
    }

    // gates: the velocity is weighted by the part of [t0, t0 + dt] inside
    // [startTime, endTime] so that the displacement is exactly
    // velocity*(min(t, endTime) - startTime) whatever the time steps
    for (const gate& g : gates_)
    {
        const scalar t1 = t0 + dt;
        const scalar on =
            max(scalar(0), min(t1, g.endTime) - max(t0, g.startTime));
        const scalar f = dt > 0 ? min(on/dt, scalar(1)) : 0;
        system_->setWallVelocity(g.wallId, toVec3(f*g.velocity));
    }

    applyFrontRearWalls();
    oldPositions_ = system_->positions();
    lastRemoved_.clear();
    try
    {
        report_ = system_->advance(dt, maxDisplacementFraction_);
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
        if (!std::isfinite(x.x()) || !std::isfinite(x.y()) || !std::isfinite(x.z()))
        {
            FatalErrorInFunction
                << "Non-finite grain position at time " << mesh_.time().timeName()
                << ". The last written time holds the last good state." << nl
                << "    Fix: reduce deltaT or maxDisplacementFraction."
                << exit(FatalError);
        }
    }

    recordStepHealth();
    checkInsideMesh();

    if (gates_.size())
    {
        const label oldPrecision = Info().precision(17);
        forAll(gates_, gatei)
        {
            Info<< "gate " << gates_[gatei].name << " displacement "
                << gateDisplacement(gatei) << nl;
        }
        Info().precision(oldPrecision);
    }

    Info<< "NSCD: contacts " << report_.contacts
        << ", sub-steps " << report_.substeps
        << ", sweeps " << report_.sweeps
        << ", residual " << report_.residual
        << (report_.converged ? "" : " (NOT converged)")
        << ", max overlap/d_min "
        << report_.maxOverlap/max(system_->minDiameter(), VSMALL)
        << endl;

    for (const auto& f : postEvolve_)
    {
        if (f.second)
        {
            f.second();
        }
    }
    return report_;
}


void Foam::grainCloud::setPostEvolve
(
    const word& name,
    std::function<void()> f
)
{
    for (auto& e : postEvolve_)
    {
        if (e.first == name)
        {
            e.second = std::move(f);
            return;
        }
    }
    postEvolve_.emplace_back(name, std::move(f));
}


Foam::scalar Foam::grainCloud::kineticEnergy() const
{
    scalar e = 0;
    for (std::size_t i = 0; i < system_->size(); ++i)
    {
        if (system_->fixed(i)) continue;
        e += 0.5*system_->mass(i)*system_->velocities()[i].squaredNorm()
           + 0.5*system_->inertia(i)*system_->angularVelocities()[i].squaredNorm();
    }
    return e;
}


bool Foam::grainCloud::heatOn() const
{
    for (const int m : system_->materials())
    {
        if (system_->material(m).heatCapacity > 0)
        {
            return true;
        }
    }
    return false;
}


Foam::scalar Foam::grainCloud::meanTemperature() const
{
    scalar s = 0;
    label n = 0;
    for (std::size_t i = 0; i < system_->size(); ++i)
    {
        if
        (
            system_->material(system_->materials()[i]).heatCapacity > 0
         && !system_->fixedTemperature(i)
        )
        {
            s += system_->temperatures()[i];
            ++n;
        }
    }
    return n > 0 ? s/n : 0;
}


Foam::List<Foam::scalar> Foam::grainCloud::temperatures() const
{
    const std::vector<double>& T = system_->temperatures();
    List<scalar> l(T.size());
    forAll(l, i)
    {
        l[i] = T[i];
    }
    return l;
}


Foam::List<std::pair<Foam::word, Foam::scalar>>
Foam::grainCloud::wallHeatRates(scalar dt) const
{
    List<std::pair<word, scalar>> rates(wallTemperatures_.size());
    HashTable<label> wallSlot;
    forAll(wallTemperatures_, k)
    {
        rates[k] = std::make_pair(wallTemperatures_[k].first, scalar(0));
        for (const label id : patchWalls_[wallTemperatures_[k].first])
        {
            wallSlot.set(Foam::name(id), k);
        }
    }
    const scalar dtSub = dt/max(report_.substeps, 1);
    const std::vector<double>& T = system_->temperatures();
    for (const nscd::System::ContactView& c : system_->contacts())
    {
        if (c.j >= 0) continue;
        const label w = -c.j - 1;
        const auto iter = wallSlot.cfind(Foam::name(w));
        if (!iter.found()) continue;
        const label i = c.i;
        if
        (
            system_->material(system_->materials()[i]).heatCapacity > 0
         && !system_->fixedTemperature(i)
        )
        {
            const scalar H = system_->contactConductance(c, dtSub);
            rates[iter.val()].second += H*(system_->wallTemperature(w) - T[i]);
        }
    }
    return rates;
}


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

    // HDF5 state (grains are held whole on every rank: each writes its
    // copy; in parallel the master also writes the undecomposed case's, so
    // that reconstructPar gives time directories a serial run continues from)
    writeStateFile(runTime.timePath()/stateFileName);
    if (Pstream::parRun() && Pstream::master())
    {
        const fileName global(runTime.globalPath()/runTime.timeName());
        mkDir(global);
        writeStateFile(global/stateFileName);
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
    // lies in this rank's part of the mesh; a centre on a processor
    // boundary is found by both sides: the lowest rank writes it, so that
    // reconstructPar gives every grain once
    passiveParticleCloud cloud(mesh_, cloudName, IDLList<passiveParticle>());
    // origId 0, 1, ... at every write (not a count over the run): the same
    // grains give the same files (the start time is rewritten at start)
    particle::particleCount_ = 0;
    const label n = system_->size();
    labelList cells(n, -1);
    labelList owner(n, labelMax);
    for (label i = 0; i < n; ++i)
    {
        cells[i] = mesh_.findCell(meshPosition(i));
        if (cells[i] >= 0)
        {
            owner[i] = Pstream::myProcNo();
        }
    }
    if (Pstream::parRun())
    {
        Pstream::listCombineGather(owner, minEqOp<label>());
        Pstream::listCombineScatter(owner);
    }
    DynamicList<label> ids(n);
    for (label i = 0; i < n; ++i)
    {
        if (cells[i] >= 0 && owner[i] == Pstream::myProcNo())
        {
            cloud.addParticle(new passiveParticle(mesh_, meshPosition(i), cells[i]));
            ids.append(i);
        }
    }

    IOField<scalar> d(cloud.fieldIOobject("d", IOobject::NO_READ), ids.size());
    IOField<vector> U(cloud.fieldIOobject("U", IOobject::NO_READ), ids.size());
    IOField<vector> omega(cloud.fieldIOobject("omega", IOobject::NO_READ), ids.size());
    IOField<label> grainId(cloud.fieldIOobject("grainId", IOobject::NO_READ), ids.size());
    IOField<label> fixed(cloud.fieldIOobject("fixed", IOobject::NO_READ), ids.size());
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
    const bool valid = ids.size() > 0;
    d.write(valid);
    U.write(valid);
    omega.write(valid);
    grainId.write(valid);
    fixed.write(valid);
    for (const auto& ex : extra)
    {
        IOField<vector> f(cloud.fieldIOobject(ex.first, IOobject::NO_READ), ids.size());
        forAll(ids, k)
        {
            f[k] = (*ex.second)[ids[k]];
        }
        f.write(valid);
    }
    for (const auto& ex : extraScalars)
    {
        IOField<scalar> f(cloud.fieldIOobject(ex.first, IOobject::NO_READ), ids.size());
        forAll(ids, k)
        {
            f[k] = (*ex.second)[ids[k]];
        }
        f.write(valid);
    }
}
