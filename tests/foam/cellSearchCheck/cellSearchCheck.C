// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: cellSearchCheck (test application)

Description
    Check of grainCloud's cell search (src/grainCloud/grainMeshExits.H)
    against OpenFOAM's polyMesh::findCell on the case's mesh.  Why: on a
    one-cell-thick 2D mesh polyMesh's cell octree stops refining (every
    cell spans the thickness), so grainMeshExits searches its own octree
    on a box as deep as it is wide; both must name the same cell.

    Reference: polyMesh::findCell (OpenFOAM's octree, the same CELL_TETS
    point-in-cell test) at nPoints random points of the mesh's bounding
    box widened by 10 % (inside and outside the mesh; 2D: in the plane
    z = zMid of the grains).  findCellFrom is tried from a random hint
    cell for each point.  Writes <case>/cellSearchCheck (a dictionary):
        points          points tested
        inside          points polyMesh::findCell puts in a cell
        findCellMismatches      points where findCell differs
        findCellFromMismatches  points where findCellFrom differs
        searchSeconds   CPU time of findCell over the points, its
                        octree's construction included [s]
        referenceSeconds  the same for polyMesh::findCell [s]
    Usage: cellSearchCheck -case <case> [-points N] [-twoD]
\*---------------------------------------------------------------------------*/

#include "fvCFD.H"
#include "Random.H"
#include "cpuTime.H"
#include "grainMeshExits.H"

using namespace Foam;

int main(int argc, char *argv[])
{
    argList::noParallel();
    argList::addOption("points", "N", "random points (default 20000)");
    argList::addBoolOption("twoD", "grains in the plane z = zMid (2D)");
    #include "setRootCase.H"
    #include "createTime.H"
    #include "createMesh.H"

    const label nPoints = args.lookupOrDefault<label>("points", 20000);
    const bool twoD = args.found("twoD");
    const boundBox bb(mesh.points(), false);
    const scalar zMid = 0.5*(bb.min().z() + bb.max().z());
    const grainMeshExits exits(mesh, twoD ? 2 : 3, zMid);

    Random rnd(1234);
    pointField pts(nPoints);
    labelList hints(nPoints);
    const vector span(bb.span());
    forAll(pts, i)
    {
        point p = bb.min() - 0.05*span + cmptMultiply(1.1*span, rnd.sample01<vector>());
        if (twoD)
        {
            p.z() = zMid;
        }
        pts[i] = p;
        hints[i] = rnd.position<label>(0, mesh.nCells() - 1);
    }

    labelList ref(nPoints), found(nPoints), fromHint(nPoints);
    cpuTime timer;
    forAll(pts, i)
    {
        found[i] = exits.findCell(pts[i]);
    }
    const scalar searchSeconds = timer.cpuTimeIncrement();
    forAll(pts, i)
    {
        ref[i] = mesh.findCell(pts[i]);
    }
    const scalar referenceSeconds = timer.cpuTimeIncrement();
    forAll(pts, i)
    {
        fromHint[i] = exits.findCellFrom(pts[i], hints[i]);
    }

    label inside = 0, mismatches = 0, fromMismatches = 0;
    forAll(pts, i)
    {
        inside += ref[i] >= 0;
        mismatches += found[i] != ref[i];
        fromMismatches += fromHint[i] != ref[i];
    }

    OFstream os(runTime.path()/"cellSearchCheck");
    os  << "points " << nPoints << ";" << nl
        << "inside " << inside << ";" << nl
        << "findCellMismatches " << mismatches << ";" << nl
        << "findCellFromMismatches " << fromMismatches << ";" << nl
        << "searchSeconds " << searchSeconds << ";" << nl
        << "referenceSeconds " << referenceSeconds << ";" << nl;
    Info<< nPoints << " points, " << inside << " inside: findCell "
        << mismatches << " and findCellFrom " << fromMismatches
        << " mismatches; " << searchSeconds << " s against polyMesh::findCell "
        << referenceSeconds << " s" << nl << "End" << nl << endl;
    return 0;
}
