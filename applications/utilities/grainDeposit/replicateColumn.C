// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam

Description
    grainDeposit method replicate (replicateColumn.H).
\*---------------------------------------------------------------------------*/

#include "replicateColumn.H"
#include "grainDictionaryTools.H"
#include "error.H"

#include <array>
#include <cmath>

namespace
{

using namespace Foam;

//- Path of replicate.source (environment variables expanded; relative to
//  caseDir unless absolute).
fileName sourcePath(const dictionary& rd, const fileName& caseDir)
{
    fileName source = rd.get<fileName>("source");
    source.expand();
    if (!source.isAbsolute())
    {
        source = caseDir/source;
    }
    return source;
}


//- Number of copies, replicate.copies.  Error: FatalIOError when < 1.
label readCopies(const dictionary& rd)
{
    const label k = rd.get<label>("copies");
    if (k < 1)
    {
        FatalIOErrorInFunction(rd)
            << "copies " << k << " in " << rd.name() << " must be >= 1"
            << exit(FatalIOError);
    }
    return k;
}


//- The column's grain system read from source (a grainState.h5).  Errors
//  (FatalIOError naming rd): unreadable source, dimension other than dim.
nscd::System readColumn
(
    const dictionary& rd,
    const fileName& source,
    const label dim
)
{
    nscd::System col = [&]()
    {
        try
        {
            return nscd::System::readHDF5(source);
        }
        catch (const nscd::InputError& err)
        {
            FatalIOErrorInFunction(rd)
                << "Cannot read the column of replicate.source " << source
                << " in " << rd.name() << ": " << err.what() << nl
                << "    Fix: settle the column first (grainDeposit in its"
                << " case) and give the path of its <time>/grainState.h5"
                << exit(FatalIOError);
        }
        return nscd::System(dim);
    }();
    if (col.dimension() != dim)
    {
        FatalIOErrorInFunction(rd)
            << "replicate.source " << source << " holds a " << col.dimension()
            << "D grain system but the mesh is " << dim << "D"
            << exit(FatalIOError);
    }
    return col;
}


//- Checks that every grain of the column is movable and lies within the
//  column [x0, x0 + w] [m] (to 1 % of the smallest radius); k: the number
//  of copies (named in the message).  Errors: FatalIOError naming rd.
void checkColumn
(
    const dictionary& rd,
    const fileName& source,
    const nscd::System& col,
    const double x0,
    const double w,
    const label k
)
{
    const label n = label(col.size());
    const double rMin = 0.5*col.minDiameter();
    for (label i = 0; i < n; ++i)
    {
        const double x = col.positions()[i].x(), r = col.radii()[i];
        if (col.fixed(i))
        {
            FatalIOErrorInFunction(rd)
                << "replicate.source " << source << " has fixed grain " << i
                << "; replicate copies a settled column of movable grains."
                << exit(FatalIOError);
        }
        if (x - r < x0 - 1e-2*rMin || x + r > x0 + w + 1e-2*rMin)
        {
            FatalIOErrorInFunction(rd)
                << "Grain " << i << " of replicate.source " << source
                << " spans x = [" << x - r << ", " << x + r << "], outside"
                << " the column [" << x0 << ", " << x0 + w << "] (mesh width / "
                << k << " copies)." << nl
                << "    Fix: settle the column between side walls at x = "
                << x0 << " and " << x0 + w << ", or change copies"
                << exit(FatalIOError);
        }
    }
}


//- Side of a side-wall contact: -1 left wall (normal along +x), +1 right
//  wall (normal along -x), 0 not a side-wall contact.
int side(const nscd::System::ContactView& c)
{
    return c.j < 0 && std::abs(c.normal.x()) > 1 - 1e-9
        ? (c.normal.x() > 0 ? -1 : 1) : 0;
}


//- The wall ids j of the left and right side walls in the contacts cv
//  (0: no contact with that side).  Sets out.sideContacts (their number)
//  and out.sideFriction (their tangential over normal impulse [-]).
std::array<int, 2> sideWalls
(
    const std::vector<nscd::System::ContactView>& cv,
    replicatedColumn& out
)
{
    std::array<int, 2> wallOf = {0, 0};   // wall j of the left / right side
    double frictional = 0, normal = 0;
    for (const auto& c : cv)
    {
        const int s = side(c);
        if (s == 0) continue;
        wallOf[s > 0] = c.j;
        ++out.sideContacts;
        const double pn = c.impulse.dot(c.normal);
        normal += std::abs(pn);
        frictional += (c.impulse - pn*c.normal).norm();
    }
    out.sideFriction = normal > 0 ? frictional/normal : 0;
    return wallOf;
}


//- Appends copy c (of k; mirrored when c is odd) of the column col to out:
//  its grains, shifted by c w [m] (or mirrored about x0 + (c + 1) w), and
//  its contacts cv (normals and impulses [N s] mirrored with it).  A
//  side-wall contact becomes the normal impulse on the grain's mirror image
//  in the next copy, or stays a contact with the wall wallOf of that side
//  on the outer sides (dropped if the source had none).
void appendCopy
(
    const nscd::System& col,
    const std::vector<nscd::System::ContactView>& cv,
    const label c,
    const label k,
    const double x0,
    const double w,
    const std::array<int, 2>& wallOf,
    replicatedColumn& out
)
{
    const label n = label(col.size());
    const bool mirrored = c % 2 == 1;
    const auto mapV = [mirrored](const nscd::Vec3& v)
    {
        return mirrored ? nscd::Vec3(-v.x(), v.y(), v.z()) : v;
    };
    for (label i = 0; i < n; ++i)
    {
        nscd::Vec3 x = col.positions()[i];
        x.x() = mirrored ? x0 + (c + 1)*w - (x.x() - x0) : x.x() + c*w;
        out.grains.push_back({x, 2*col.radii()[i]});
    }
    const int off = int(c*n);
    for (const auto& v : cv)
    {
        nscd::System::ContactView m = v;
        m.i = v.i + off;
        m.normal = mapV(v.normal);
        m.impulse = mapV(v.impulse);
        const int s = side(v);
        if (s == 0)
        {
            if (v.j >= 0) m.j = v.j + off;
            out.contacts.push_back(m);
            continue;
        }
        // side of this copy (-1 left, +1 right) and its plane index
        const int cs = mirrored ? -s : s;
        const label plane = cs < 0 ? c : c + 1;
        if (plane == 0 || plane == k)
        {
            const int wall = wallOf[cs > 0];   // outer wall (source ids)
            if (wall == 0) continue;
            m.j = wall;
            out.contacts.push_back(m);
        }
        else if (cs > 0)
        {
            // the grain's mirror image in copy c + 1: normal impulse only
            m.j = v.i + off + int(n);
            m.impulse = m.normal*m.impulse.dot(m.normal);
            out.contacts.push_back(m);
        }
    }
}

} // End anonymous namespace


Foam::replicatedColumn Foam::replicateColumn
(
    const dictionary& dict,
    const fileName& caseDir,
    const boundBox& meshBounds,
    const label dim
)
{
    const dictionary& rd = dict.subDict("replicate");
    grainTools::checkKeywords(rd, {"source", "copies"});
    const fileName source = sourcePath(rd, caseDir);
    const label k = readCopies(rd);

    const nscd::System col = readColumn(rd, source, dim);

    const double x0 = meshBounds.min().x();
    const double w = (meshBounds.max().x() - x0)/k;
    checkColumn(rd, source, col, x0, w, k);

    replicatedColumn out;
    out.dt = col.lastStepDt();
    const std::vector<nscd::System::ContactView> cv = col.contacts();
    if (cv.empty() || !(out.dt > 0))
    {
        FatalIOErrorInFunction(rd)
            << "replicate.source " << source << " holds no contact impulses"
            << " (a column at rest on its floor has some)." << nl
            << "    Fix: write the column with `writeContactImpulses yes;` in"
            << " its system/grainDepositDict" << exit(FatalIOError);
    }

    const std::array<int, 2> wallOf = sideWalls(cv, out);
    for (label c = 0; c < k; ++c)
    {
        appendCopy(col, cv, c, k, x0, w, wallOf, out);
    }
    return out;
}
