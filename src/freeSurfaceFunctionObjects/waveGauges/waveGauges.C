// SPDX-License-Identifier: GPL-3.0-or-later
#include "waveGauges.H"
#include "freeSurfaceTools.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(waveGauges, 0);
    addToRunTimeSelectionTable(functionObject, waveGauges, dictionary);
}
}


void Foam::functionObjects::waveGauges::buildColumns()
{
    // The gauge is the vertical line P0(x) + s v, with P0 = x h + c w: w the
    // third direction (h x v; 2D: the mesh normal), c the mesh centre along
    // w (2D: mid-depth).  For each cell the part of the line inside it is
    // found by clipping against the cell's face planes (Cyrus-Beck; exact
    // for convex cells: hexahedra, prisms of extruded triangles, tetrahedra;
    // faces taken planar through their centre with their area normal), so
    // the column is exact on any such mesh, structured or not.
    const vectorField& Cf = mesh_.faceCentres();
    const vectorField& Sf = mesh_.faceAreas();
    const labelList& own = mesh_.faceOwner();
    const pointField& pts = mesh_.points();
    vector w = horizontal_ ^ vertical_;
    w /= max(mag(w), VSMALL);
    const scalar c = mesh_.bounds().centre() & w;

    cells_.setSize(x_.size());
    extent_.setSize(x_.size());
    eta_.setSize(x_.size(), 0);
    forAll(x_, gi)
    {
        const point P0 = x_[gi]*horizontal_ + c*w;
        DynamicList<label> cs;
        DynamicList<Tuple2<scalar, scalar>> ex;
        forAll(mesh_.cells(), celli)
        {
            // quick reject on the horizontal extent
            scalar hmin = GREAT, hmax = -GREAT;
            for (const label pi : mesh_.cellPoints()[celli])
            {
                const scalar h = pts[pi] & horizontal_;
                hmin = min(hmin, h);
                hmax = max(hmax, h);
            }
            const scalar tol = 1e-9*(hmax - hmin);
            if (x_[gi] < hmin - tol || x_[gi] > hmax + tol)
            {
                continue;
            }
            scalar slo = -GREAT, shi = GREAT;
            bool inside = true;
            for (const label facei : mesh_.cells()[celli])
            {
                // outward unit normal of the face seen from this cell
                vector n = Sf[facei]/max(mag(Sf[facei]), VSMALL);
                if (own[facei] != celli)
                {
                    n = -n;
                }
                const scalar d = (P0 - Cf[facei]) & n;   // < 0: inside
                const scalar nv = n & vertical_;
                if (mag(nv) < 1e-12)
                {
                    // face parallel to the line: the line is inside, outside
                    // or on it; a gauge on a face belongs to the cell on the
                    // +h side (half-open, as [hmin, hmax)), and on a face
                    // normal to w (3D: the mesh centre on a face between two
                    // cell layers, or a processor boundary) to the cell on
                    // the +w side, so that no cell is counted twice
                    const scalar nh = n & horizontal_;
                    const bool plusSide =
                        mag(nh) > 1e-12 ? nh > 0 : (n & w) > 0;
                    if (d > tol || (d > -tol && plusSide))
                    {
                        inside = false;
                        break;
                    }
                }
                else
                {
                    const scalar s = -d/nv;  // where the line crosses the plane
                    if (nv > 0)
                    {
                        shi = min(shi, s);
                    }
                    else
                    {
                        slo = max(slo, s);
                    }
                }
            }
            if (!inside)
            {
                continue;
            }
            slo = max(slo, vMin_);
            shi = min(shi, vMax_);
            if (shi > slo)
            {
                cs.append(celli);
                ex.append(Tuple2<scalar, scalar>(slo, shi));
            }
        }
        label n = cs.size();
        reduce(n, sumOp<label>());
        if (n == 0)
        {
            FatalErrorInFunction
                << "waveGauges " << name() << ": gauge x = " << x_[gi]
                << " crosses no cell of the mesh " << mesh_.bounds()
                << " (within range " << vMin_ << " " << vMax_ << ")." << nl
                << "    Fix: put the gauges inside the domain."
                << exit(FatalError);
        }
        cells_[gi].transfer(cs);
        extent_[gi].transfer(ex);
    }
}


Foam::functionObjects::waveGauges::waveGauges
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    writeFile(mesh_, name, typeName, dict),
    alphaName_("alpha.water"),
    stillWaterLevel_(0),
    horizontal_(1, 0, 0),
    vertical_(0, 1, 0),
    vMin_(-GREAT),
    vMax_(GREAT)
{
    read(dict);
    List<string> columns(x_.size());
    forAll(x_, gi)
    {
        columns[gi] = "eta(" + Foam::name(x_[gi]) + ")";
    }
    freeSurfaceTools::writeColumnHeader
    (
        *this,
        "Free-surface elevation [m] (column integral of " + alphaName_
      + ") minus stillWaterLevel " + Foam::name(stillWaterLevel_),
        columns
    );
}


bool Foam::functionObjects::waveGauges::read(const dictionary& dict)
{
    freeSurfaceTools::readBase(*this, dict);
    freeSurfaceTools::checkKeywords
    (
        dict,
        {
            "alpha", "x", "stillWaterLevel", "horizontalDirection",
            "verticalDirection", "range"
        }
    );
    alphaName_ = dict.getOrDefault<word>("alpha", "alpha.water");
    x_ = dict.get<scalarList>("x");
    if (x_.empty())
    {
        FatalIOErrorInFunction(dict)
            << "x in " << dict.name() << " is empty. Fix: list the gauge"
            << " abscissae, e.g. x (0.5 1.0);" << exit(FatalIOError);
    }
    stillWaterLevel_ = dict.getOrDefault<scalar>("stillWaterLevel", 0);
    freeSurfaceTools::getFrame(dict, horizontal_, vertical_);
    const Pair<scalar> range = freeSurfaceTools::getRange(dict, "range");
    vMin_ = range.first();
    vMax_ = range.second();
    buildColumns();
    return true;
}


bool Foam::functionObjects::waveGauges::execute()
{
    tmp<volScalarField> talpha =
        freeSurfaceTools::lookupOrRead(mesh_, alphaName_);
    const scalarField& alpha = talpha().primitiveField();
    forAll(x_, gi)
    {
        scalar bottom = GREAT, h = 0;
        forAll(cells_[gi], k)
        {
            const Tuple2<scalar, scalar>& e = extent_[gi][k];
            bottom = min(bottom, e.first());
            h += min(max(alpha[cells_[gi][k]], scalar(0)), scalar(1))
                *(e.second() - e.first());
        }
        reduce(bottom, minOp<scalar>());
        reduce(h, sumOp<scalar>());
        eta_[gi] = bottom + h - stillWaterLevel_;
    }
    Log << type() << " " << name() << ": eta = " << flatOutput(eta_) << endl;
    return true;
}


bool Foam::functionObjects::waveGauges::write()
{
    if (writeToFile() && Pstream::master())
    {
        writeCurrentTime(file());
        for (const scalar e : eta_)
        {
            file() << tab << e;
        }
        file() << endl;
    }
    return true;
}
