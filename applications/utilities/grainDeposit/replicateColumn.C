/*---------------------------------------------------------------------------*\
  nscdFoam

Description
    grainDeposit method replicate (replicateColumn.H).
\*---------------------------------------------------------------------------*/

#include "replicateColumn.H"
#include "grainDictionaryTools.H"
#include "error.H"

#include <cmath>

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
    fileName source = rd.get<fileName>("source");
    source.expand();
    if (!source.isAbsolute())
    {
        source = caseDir/source;
    }
    const label k = rd.get<label>("copies");
    if (k < 1)
    {
        FatalIOErrorInFunction(rd)
            << "copies " << k << " in " << rd.name() << " must be >= 1"
            << exit(FatalIOError);
    }

    const nscd::System col = [&]()
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

    const label n = label(col.size());
    const double x0 = meshBounds.min().x();
    const double w = (meshBounds.max().x() - x0)/k;
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

    // side-wall contacts: normal along +x (left wall) or -x (right wall)
    auto side = [](const nscd::System::ContactView& c)
    {
        return c.j < 0 && std::abs(c.normal.x()) > 1 - 1e-9
            ? (c.normal.x() > 0 ? -1 : 1) : 0;
    };
    int wallOf[2] = {0, 0};   // wall j of the left / right side (0: none)
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

    for (label c = 0; c < k; ++c)
    {
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
    return out;
}
