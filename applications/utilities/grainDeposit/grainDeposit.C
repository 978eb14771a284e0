// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam

Application
    grainDeposit

Description
    Creates the initial grains of a case: fills a box or a cellZone with
    polydisperse grains (diameters uniform in [dMin, sizeRatio*dMin], seeded
    random) on a loose jittered lattice, or takes an explicit list, then lets
    them settle under gravity (NSCD, constant/grainProperties, constant/g)
    until the largest grain speed falls below a tolerance.  Temporary walls
    (planes) may hold the packing during settling only (e.g. the gate of a
    column collapse, removed at release).

    Writes <startTime>/grainState.h5 and <startTime>/lagrangian/grains.

    system/grainDepositDict
    \verbatim
    material    glass;              // a material of constant/grainProperties
    method      box;                // box | cellZone | rain | list | replicate
    box         { min (0 0 0); max (0.1 0.2 0); }   // method box, rain
    cellZone    column;             // method cellZone
    grains      ((x y z d) ...);    // method list
    fixed       no;                 // method list: yes = all listed grains
                                    // fixed
    replicate                       // method replicate: a settled column
    {                               // copied across the mesh (x), every
        source  "../column/0/grainState.h5";  // other copy mirrored, with
        copies  18;                 // its contact impulses (replicateColumn.H;
                                    // the source written with
                                    // writeContactImpulses yes)
    }
                                    // method rain (2D): the grains laid one
                                    // by one over the box's floor, each rolled
                                    // to rest on two below (rainDeposit.H)
    staticLoad  no;                 // method rain: yes = the settling starts
                                    // from their static contact forces
                                    // (nscd/StaticLoad.H): 13-29x cheaper in
                                    // a column ten grains wide, 3x dearer in
                                    // a wide bed (src/nscd/README.md)
    number      2000;               // box/cellZone/rain: number of grains ...
    // solidFraction 0.3;           // ... or fraction of the region's volume
    dMin        2e-3;               // [m]
    sizeRatio   1.2;                // lambda = d_max/d_min (>= 1)
    seed        1;
    fixedRow    { from (0 0.001 0); to (0.5 0.001 0); diameter 2e-3; }
                                    // optional rough floor
    initialVelocity (0 0 0);        // [m/s] optional: the velocity of every
                                    // movable grain in the written state
                                    // (after the settling), e.g. a slide
                                    // launched at a given speed; fixed
                                    // grains stay at rest; 2D: z must be 0
    writeContactImpulses no;        // yes: the settled contact impulses are
                                    // written with the grains (warm start of
                                    // the run; needed by a replicate source);
                                    // default yes with a compliant material
                                    // (its overlaps carry those impulses)
    settle                          // optional: no settling without it
    {
        maxTime     5;              // [s] simulated
        deltaT      1e-3;           // [s]
        speedTolerance 1e-3;        // [m/s] at rest when max |v| below this
        temporaryWalls ( { point (0.1 0 0); normal (-1 0 0); } );
    }
    \endverbatim
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "depositMethods.H"
#include "nscd/StaticLoad.H"
#include "grainDictionaryTools.H"
#include "contactSolverColumns.H"
#include "grainRunControl.H"
#include "fvCFD.H"

#include <cmath>
#include <utility>

#include <random>
#include <algorithm>

using namespace Foam;

namespace
{

// The functions below take system/grainDepositDict as the IOdictionary it
// is: its name() is then the object's name (grainDepositDict), which the
// messages print, not the file's path (dictionary::name()).

//- A temporary wall of the settling: a point on it [m] and its unit normal
//  (towards the grains), both in the grain system's frame
typedef std::pair<nscd::Vec3, nscd::Vec3> wallPlane;

//- The fixed grains left out of the settling, and the index in the written
//  system of each grain of the settling system
struct fixedPlacement
{
    //- Fixed grains added after the settling (behind a temporary wall or
    //  taking part in it), in written order
    std::vector<grainSpec> fixedLater;
    //- Written index of each settling grain: the movable ones keep theirs,
    //  the fixed ones follow in fixedLater order
    std::vector<int> writtenIndex;
};

//- Adds the movable grains of specs (material matId) to the settling system
//  and returns the fixed ones: all of specs with method list and
//  `fixed yes;` (a packed bed), none otherwise.
std::vector<grainSpec> addMovableGrains
(
    const IOdictionary& depositDict,
    const word& method,
    const std::vector<grainSpec>& specs,
    grainCloud& settling,
    const label matId
)
{
    // method list: `fixed yes;` makes every listed grain fixed (a packed bed)
    const bool listFixed =
        method == "list" && depositDict.getOrDefault<bool>("fixed", false);
    std::vector<grainSpec> fixedSpecs;
    for (const grainSpec& s : specs)
    {
        if (listFixed)
        {
            fixedSpecs.push_back(s);
        }
        else
        {
            settling.system().addGrain(s.x, 0.5*s.d, matId);
        }
    }
    return fixedSpecs;
}


//- Optional fixedRow { from; to; diameter; }: a row of fixed, touching
//  grains (a rough floor, as in Staron & Hinch 2005) from `from` to `to`
//  [m], diameter [m], appended to fixedSpecs; logs their number.  Errors:
//  FatalIOError for an unknown keyword or a diameter not positive.
void addFixedRow
(
    const IOdictionary& depositDict,
    const grainCloud& settling,
    std::vector<grainSpec>& fixedSpecs
)
{
    if (depositDict.found("fixedRow"))
    {
        const dictionary& fr = depositDict.subDict("fixedRow");
        grainTools::checkKeywords(fr, {"from", "to", "diameter"});
        const nscd::Vec3 a = settling.toSystem(fr.get<vector>("from"));
        const nscd::Vec3 b = settling.toSystem(fr.get<vector>("to"));
        const scalar d = grainTools::getPositive(fr, "diameter");
        const label n = label((b - a).norm()/d) + 1;
        for (label k = 0; k < n; ++k)
        {
            const nscd::Vec3 x =
                n > 1 ? nscd::Vec3(a + (b - a)*(scalar(k)/(n - 1))) : a;
            fixedSpecs.push_back({x, d});
        }
        Info<< "Placed a row of " << n << " fixed grains" << endl;
    }
}


//- The temporary walls of settle { temporaryWalls ( { point; normal; } ...
//  ); } (settling only), in the grain system's frame, normals made unit.
//  Errors: FatalIOError for an unknown keyword or a zero normal.
std::vector<wallPlane> temporaryPlanes
(
    const IOdictionary& depositDict,
    const grainCloud& settling
)
{
    List<dictionary> temporaryWalls;
    if
    (
        depositDict.found("settle")
     && depositDict.subDict("settle").found("temporaryWalls")
    )
    {
        temporaryWalls =
            depositDict.subDict("settle")
                .get<List<dictionary>>("temporaryWalls");
    }
    std::vector<wallPlane> planes;
    for (const dictionary& w : temporaryWalls)
    {
        grainTools::checkKeywords(w, {"point", "normal"});
        const vector n = w.get<vector>("normal");
        if (mag(n) < VSMALL)
        {
            FatalIOErrorInFunction(w)
                << "temporaryWalls: zero normal" << exit(FatalIOError);
        }
        planes.push_back
        (
            {
                settling.toSystem(w.get<vector>("point")),
                settling.toSystem(n/mag(n))
            }
        );
    }
    return planes;
}


//- Adds the fixed grains (material matId) and the temporary walls to the
//  settling system.  Fixed grains behind a temporary wall take no part in
//  the settling (nothing reaches them) and join the system afterwards; a
//  fixed grain cut by a temporary wall is left out altogether (it would
//  overlap the wall during settling and the settled grains after it).
//  Returns the fixed grains to write and the written index of each grain
//  of the settling system.
fixedPlacement addFixedGrainsAndWalls
(
    const std::vector<grainSpec>& fixedSpecs,
    const std::vector<wallPlane>& planes,
    grainCloud& settling,
    const label matId
)
{
    fixedPlacement out;
    std::vector<grainSpec>& fixedLater = out.fixedLater;
    std::vector<int>& writtenIndex = out.writtenIndex;
    const std::size_t nMovable = settling.system().size();
    writtenIndex.resize(nMovable);
    for (std::size_t i = 0; i < writtenIndex.size(); ++i)
    {
        writtenIndex[i] = int(i);
    }
    for (const grainSpec& f : fixedSpecs)
    {
        scalar dist = GREAT;
        for (const auto& pl : planes)
        {
            dist = min(dist, (f.x - pl.first).dot(pl.second));
        }
        if (dist >= 0.5*f.d)
        {
            settling.system().addGrain(f.x, 0.5*f.d, matId, true);
            writtenIndex.push_back(int(nMovable + fixedLater.size()));
            fixedLater.push_back(f);
        }
        else if (dist <= -0.5*f.d)
        {
            fixedLater.push_back(f);
        }
    }
    for (const auto& pl : planes)
    {
        settling.system().addPlane(pl.first, pl.second);
    }
    return out;
}


//- Starts the settling from the contact impulses seedContacts [N s] of a
//  step seedDt [s] (method replicate), if any.  The column's wall ids are
//  the mesh walls' when both meshes have the same wall patches; a seed that
//  matches no detected contact is simply not used by the warm start.
void seedContactImpulses
(
    grainCloud& settling,
    const std::vector<nscd::System::ContactView>& seedContacts,
    const double seedDt
)
{
    if (!seedContacts.empty())
    {
        std::vector<nscd::System::ContactView> seed;
        for (const auto& c : seedContacts)
        {
            if (c.j >= 0 || -c.j - 1 < settling.system().nWalls())
            {
                seed.push_back(c);
            }
        }
        settling.system().setContactImpulses(seed, seedDt);
    }
}


//- Seeds the warm start of the settling with contact forces that hold the
//  grains at rest under gravity, from the top down, inside the Coulomb
//  cones of the smallest friction of the grains and walls
//  (nscd/StaticLoad.H; grains touching within 1e-9 d_min), as impulses of
//  a step dt [s]; logs the grains it could not balance.  The movable grains
//  are those of method rain, in laying order (addMovableGrains), so the load
//  path is the reverse order.
void seedStaticLoad(grainCloud& settling, const scalar dt)
{
    nscd::System& sys = settling.system();
    std::vector<int> order;
    for (int i = int(sys.size()) - 1; i >= 0; --i)
    {
        if (!sys.fixed(i)) order.push_back(i);
    }
    // the network's friction: the smallest of the grains' and the walls'
    scalar mu = GREAT;
    for (int i = 0; i < int(sys.size()); ++i)
    {
        mu = min(mu, sys.material(sys.materials()[i]).friction);
    }
    for (int w = 0; w < sys.nWalls(); ++w)
    {
        if (sys.wallFriction(w) >= 0) mu = min(mu, sys.wallFriction(w));
    }
    const nscd::StaticLoad sl = nscd::staticLoad
    (
        sys, sys.touchingContacts(1e-9*sys.minDiameter()), dt, order,
        mu < GREAT ? mu : 0
    );
    sys.setContactImpulses(sl.contacts, dt);
    Info<< "Static load: " << sl.contacts.size() << " contacts seeded, "
        << sl.unbalanced << " grains not balanced by their supports"
        << " (largest imbalance " << sl.maxImbalance << " of a weight)"
        << endl;
}


//- Velocity noise [m/s] that the contact solver's stopping test leaves in
//  a bed at rest: (N/2) tolerance d_min/dt, N = the bed's depth along
//  gravity in smallest diameters (src/nscd/README.md, "Tolerance and bed
//  depth": measured on columns 15-60 layers deep); 0 without grains or
//  gravity.
double solverSpeedNoise(const nscd::System& sys, const double dt)
{
    const double gn = sys.gravity().norm();
    if (sys.size() == 0 || !(gn > 0)) return 0;
    const nscd::Vec3 up = -sys.gravity()/gn;
    double lo = GREAT, hi = -GREAT;
    for (const nscd::Vec3& x : sys.positions())
    {
        lo = min(lo, x.dot(up));
        hi = max(hi, x.dot(up));
    }
    const double dMin = sys.minDiameter();
    const double layers = (hi - lo)/dMin + 1;
    return 0.5*layers*sys.settings().tolerance*dMin/dt;
}


//- Lets the grains settle under gravity, settle { maxTime [s]; deltaT [s];
//  speedTolerance [m/s]; }: steps of deltaT until maxTime, or until the
//  largest grain speed falls below speedTolerance (after 20 steps); logs
//  the first steps and every 100th, writes every step to postProcessing/
//  grainDepositSettle/<startTime>/grainDepositSettle.dat (stepDataFile).
//  Errors: FatalIOError for an unknown keyword or a value not positive; a
//  warning if not at rest at maxTime.
void settle(const dictionary& sd, grainCloud& settling)
{
    grainTools::checkKeywords
    (
        sd, {"maxTime", "deltaT", "speedTolerance", "temporaryWalls"}
    );
    const scalar maxTime = grainTools::getPositive(sd, "maxTime");
    const scalar dt = grainTools::getPositive(sd, "deltaT");
    const scalar vTol = grainTools::getPositive(sd, "speedTolerance");
    scalar t = 0;
    label step = 0;
    scalar vmax = GREAT;
    // a row per settling step (the log shows the first and every 100th)
    List<stepDataFile::column> columns
    ({
        {"maxSpeed", "m/s", "largest grain speed"}
    });
    columns.append(grainTools::contactSolverColumns());
    stepDataFile file
    (
        settling.mesh().time(), "grainDepositSettle",
        "grainDeposit's settling steps (the log's \"settling:\" lines);"
        " Time: the settling time from its start",
        columns
    );
    const scalar dMin = settling.system().minDiameter();
    while (t < maxTime)
    {
        const nscd::StepReport r = settling.system().advance(dt, 0.1);
        t += dt;
        ++step;
        vmax = 0;
        for (const nscd::Vec3& v : settling.system().velocities())
        {
            vmax = max(vmax, v.norm());
        }
        scalarList row({vmax});
        row.append(grainTools::contactSolverValues(r, dMin));
        file.write(t, row);
        if (step <= 3 || step % 100 == 0)
        {
            Info<< "settling: t = " << t << " s, max speed " << vmax
                << " m/s, contacts " << r.contacts << ", sweeps "
                << r.sweeps << endl;
        }
        if (t > 20*dt && vmax < vTol)
        {
            break;
        }
    }
    if (vmax < vTol)
    {
        Info<< "Settled after " << t << " s (max speed " << vmax << " m/s)"
            << endl;
        return;
    }
    Info<< "Stopped settling at maxTime " << t << " s (max speed " << vmax
        << " m/s)" << endl;
    const double noise = solverSpeedNoise(settling.system(), dt);
    OStringStream advice;
    if (noise > 0.3*vTol)
    {
        advice
            << ", or tighten contactSolver.tolerance in constant/"
            << "grainProperties: the solver error adds up over the bed's "
            << "layers, a noise of about " << noise << " m/s at tolerance "
            << settling.system().settings().tolerance
            << " (src/nscd/README.md, 'Tolerance and bed depth')";
    }
    WarningInFunction
        << "Grains not at rest after maxTime " << maxTime
        << " s (max speed " << vmax << " > speedTolerance " << vTol
        << "). Increase settle.maxTime" << advice.str().c_str() << "."
        << endl;
}


//- The optional initialVelocity [m/s] of grainDepositDict in the grain
//  system's frame (zero when absent).  Errors: FatalIOError when a 2D case
//  gives a non-zero z component (the grains move in the x-y plane).
nscd::Vec3 initialVelocity(const IOdictionary& depositDict, const grainCloud& c)
{
    const vector v =
        depositDict.getOrDefault<vector>("initialVelocity", Zero);
    if (c.dimension() == 2 && mag(v.z()) > 0)
    {
        FatalIOErrorInFunction(depositDict)
            << "initialVelocity " << v << ": a 2D case's grains move in the"
            << " x-y plane; set the z component to 0"
            << exit(FatalIOError);
    }
    return c.toSystem(v);
}


//- Fills initial (an empty grainCloud of the mesh: mesh walls only) with
//  the initial state and writes it (grainState.h5 and lagrangian/grains of
//  the start time): the settled movable grains with the velocity
//  initialVelocity [m/s] (at rest by default), then the fixed grains of
//  placement (material matId), at rest.  With writeContactImpulses yes
//  (the default with a compliant material), the settled contact impulses
//  [N s] go with the grains (renumbered by
//  placement.writtenIndex; contacts with temporary walls dropped).
//  Errors: those of grainCloud::checkState.
void writeInitialState
(
    const IOdictionary& depositDict,
    const grainCloud& settling,
    const fixedPlacement& placement,
    const label matId,
    grainCloud& initial
)
{
    const nscd::System& s = settling.system();
    const nscd::Vec3 v0 = initialVelocity(depositDict, initial);
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        if (!s.fixed(i))
        {
            const int k = initial.system().addGrain
            (
                s.positions()[i], s.radii()[i], s.materials()[i]
            );
            initial.system().velocities()[k] = v0;
        }
    }
    for (const grainSpec& f : placement.fixedLater)
    {
        initial.system().addGrain(f.x, 0.5*f.d, matId, true);
    }
    // writeContactImpulses yes: the settled contact impulses go with the
    // grains (the warm start of the run, and the seed of a later `method
    // replicate`); contacts with temporary walls are dropped.  Off by
    // default: the impulses of a dry settle are not those of the run (a
    // submerged bed weighs less, a lifted gate no longer holds it), and an
    // iteration-capped solve started from them ends elsewhere than one
    // started cold (the granularCollapse regimes, tests/cases/
    // test_granularCollapse.py, moved from nonlinear transition to bore)
    // a compliant material carries the settled load by overlaps: without
    // their impulses the written bed would hold overlaps that nothing
    // carries (rejected by checkState), hence yes by default then
    bool compliant = false;
    for (int m = 0; m < s.nMaterials(); ++m)
    {
        compliant = compliant || s.material(m).compliant();
    }
    if (depositDict.getOrDefault<bool>("writeContactImpulses", compliant))
    {
        const int nMeshWalls = initial.system().nWalls();
        std::vector<nscd::System::ContactView> kept;
        for (nscd::System::ContactView c : s.contacts())
        {
            if (c.j < 0 && -c.j - 1 >= nMeshWalls) continue;
            c.i = placement.writtenIndex[c.i];
            if (c.j >= 0) c.j = placement.writtenIndex[c.j];
            kept.push_back(c);
        }
        if (s.lastStepDt() > 0)
        {
            initial.system().setContactImpulses(kept, s.lastStepDt());
        }
    }
    initial.checkState();
    initial.write();
}

} // End anonymous namespace


int main(int argc, char *argv[])
{
    argList::addNote
    (
        "Create the initial grains (box, cellZone or list) and let them"
        " settle under gravity; writes <startTime>/grainState.h5 and"
        " <startTime>/lagrangian/grains"
    );
    argList::noParallel();

    #include "setRootCase.H"
    grainRunControl::checkControlDict(args);  // writeInterval 0: SIGFPE in Time
    #include "createTime.H"
    #include "createMesh.H"

    IOdictionary depositDict
    (
        IOobject
        (
            "grainDepositDict",
            runTime.system(),
            mesh,
            IOobject::MUST_READ,
            IOobject::NO_WRITE
        )
    );
    grainTools::checkKeywords
    (
        depositDict,
        {
            "material", "method", "box", "cellZone", "grains", "number",
            "solidFraction", "dMin", "sizeRatio", "seed", "settle",
            "fixedRow", "fixed", "replicate", "writeContactImpulses",
            "staticLoad", "initialVelocity"
        }
    );

    grainCloud settling(mesh, false);
    const label matId = settling.materialId(depositDict.get<word>("material"));
    const word method = depositDict.get<word>("method");

    const depositedGrains dep =
        depositGrains(depositDict, method, mesh, settling);

    std::vector<grainSpec> fixedSpecs =
        addMovableGrains(depositDict, method, dep.specs, settling, matId);
    addFixedRow(depositDict, settling, fixedSpecs);
    const std::vector<wallPlane> planes =
        temporaryPlanes(depositDict, settling);
    const fixedPlacement placement =
        addFixedGrainsAndWalls(fixedSpecs, planes, settling, matId);

    settling.checkState();
    Info<< "Placed " << dep.specs.size() << " grains" << endl;
    seedContactImpulses(settling, dep.seedContacts, dep.seedDt);
    if (method == "rain" && depositDict.getOrDefault<bool>("staticLoad", false))
    {
        seedStaticLoad
        (
            settling,
            depositDict.found("settle")
          ? depositDict.subDict("settle").get<scalar>("deltaT") : 1.0
        );
    }

    if (depositDict.found("settle"))
    {
        settle(depositDict.subDict("settle"), settling);
    }

    // The initial state: settled grains at rest, mesh walls only
    grainCloud initial(mesh, false);
    writeInitialState(depositDict, settling, placement, matId, initial);

    Info<< "Wrote " << initial.system().size() << " grains to "
        << runTime.timePath() << nl
        << "End\n" << endl;
    return 0;
}
