// SPDX-License-Identifier: GPL-3.0-or-later
#include "vapourCohesion.H"
#include "grainDictionaryTools.H"
#include "volFields.H"
#include "PstreamCombineReduceOps.H"

#include <cmath>

const Foam::word Foam::vapourCohesion::cellHintColumn("cohesionCellHint");


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::vapourCohesion::vapourCohesion
(
    const fvMesh& mesh,
    grainCloud& grains,
    const overlapMeshAdapter& adapter
)
:
    mesh_(mesh),
    grains_(grains),
    adapter_(adapter)
{}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vapourCohesion::read(const IOdictionary& dict, const bool vapourOn)
{
    dictName_ = dict.name();
    nscd::System& s = grains_.system();
    // absent or `cohesion none;`: no cohesion
    bool none = !dict.found("cohesion");
    if (!none && !dict.isDict("cohesion"))
    {
        const ITstream& is = dict.lookup("cohesion");
        none = is.size() == 1 && is[0].isWord() && is[0].wordToken() == "none";
    }
    if (none)
    {
        // a state written by a run with cohesion keeps its force: off here
        s.setCohesion(nullptr, 0);
        s.settings().cohesionMinAge = 0;
        return;
    }
    if (!dict.isDict("cohesion"))
    {
        FatalIOErrorInFunction(dict)
            << "cohesion in " << dict.name() << " must be a sub-dictionary"
            << " { force <F_c0>; vapourThreshold <psi0>; minAge <steps>; }"
            << " (thesis eq. 4.18) or none" << exit(FatalIOError);
    }
    const dictionary& cd = dict.subDict("cohesion");
    grainTools::checkKeywords(cd, {"force", "vapourThreshold", "minAge"});
    if (!cd.found("force"))
    {
        FatalIOErrorInFunction(cd)
            << "Missing keyword force in " << cd.name() << nl
            << "    Fix: give the cohesion force F_c0 of thesis eq. 4.18, in N"
            << " (3D) or N/m per unit depth (2D), e.g. force 0.2;"
            << exit(FatalIOError);
    }
    force_ = grainTools::getPositive(cd, "force");
    minAge_ = cd.getOrDefault<label>("minAge", 0);
    if (minAge_ < 0)
    {
        FatalIOErrorInFunction(cd)
            << "minAge " << minAge_ << " in " << cd.name()
            << ": the minimum contact age (NSCD steps) must be >= 0." << nl
            << "    Fix: minAge 0; (cohesive from the first step of contact)"
            << " or a number of steps the contact must persist"
            << exit(FatalIOError);
    }
    byVapour_ = switchedByVapour(dict);
    if (byVapour_)
    {
        vapourThreshold_ = cd.get<scalar>("vapourThreshold");
        if (!std::isfinite(vapourThreshold_))
        {
            FatalIOErrorInFunction(cd)
                << "vapourThreshold in " << cd.name() << " must be finite"
                << exit(FatalIOError);
        }
        if (!vapourOn)
        {
            FatalIOErrorInFunction(cd)
                << "vapourThreshold in " << cd.name() << " switches cohesion"
                << " by the vapour field psi (thesis eq. 4.18), but vapour"
                << " transport is off." << nl
                << "    Fix: add vapour { D <m^2/s>; rho <kg/m^3>; } to"
                << " constant/transportProperties and the field 0/psi, or"
                << " remove vapourThreshold for cohesion everywhere (dry)."
                << exit(FatalIOError);
        }
    }

    s.settings().cohesionMinAge = minAge_;
    grains_.addColumn<label>(cellHintColumn, 0u, -1);
    try
    {
        if (byVapour_)
        {
            s.setCohesion
            (
                [this](int i, int j)
                {
                    return dryPairs_.find(pairKeyOfIndices(i, j)) == 1;
                },
                force_
            );
        }
        else
        {
            s.setCohesion([](int, int) { return true; }, force_);
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction << err.what() << exit(FatalError);
    }
    Info<< "vansCloud: cohesion F_c0 " << force_
        << (s.dimension() == 2 ? " N/m" : " N") << ", minAge "
        << minAge_ << " steps, ";
    if (byVapour_)
    {
        Info<< "where psi < " << vapourThreshold_;
    }
    else
    {
        Info<< "everywhere (dry)";
    }
    Info<< endl;

    List<stepDataFile::column> columns
    ({
        {"cohesiveContacts", "1", "contacts where cohesion acted (last NSCD"
         " sub-step)"},
        {"contacts", "1", "contacts of the grains"}
    });
    if (byVapour_)
    {
        columns.append
        ({"dryPairs", "1", "contact pairs looked up dry (psi < psi^0)"});
        columns.append({"wetPairs", "1", "contact pairs looked up wet"});
    }
    file_.reset
    (
        new stepDataFile
        (
            mesh_.time(), "cohesion",
            "cohesion (thesis eq. 4.18) after the grain step (the log's"
            " \"cohesion:\" line)",
            columns
        )
    );
}


void Foam::vapourCohesion::beforeGrainStep()
{
    if (byVapour_)
    {
        lookupVapour();
    }
}


void Foam::vapourCohesion::lookupVapour()
{
    if (!psi_)
    {
        FatalErrorInFunction
            << "cohesion.vapourThreshold in " << dictName_ << " needs the"
            << " vapour fraction psi, which the solver has not given"
            << " (vansCloud::setVapourFraction)." << nl << "    Fix: solve"
            << " the vapour field (vansFoam with transportProperties vapour"
            << " {} and 0/psi)." << exit(FatalError);
    }
    const volScalarField& psi = *psi_;
    const scalarField& psiI = psi.primitiveField();
    const nscd::System& s = grains_.system();
    const std::vector<nscd::System::ContactView> cs = s.contacts();
    const label nc = cs.size();
    const bool twoD = s.dimension() == 2;
    const overlapMapping::CellMesh& cm = adapter_.cellMesh();
    UList<label> cellHint(grains_.column<label>(cellHintColumn));

    // 1 dry, 0 wet, -1 contact point not in a local cell
    labelList state(nc, -1);
    DynamicList<point> elsewhere;  // (decomposed) those points, in order
    DynamicList<label> elsewhereContact;
    for (label k = 0; k < nc; ++k)
    {
        const nscd::System::ContactView& c = cs[k];
        const nscd::Vec3& xi = s.positions()[c.i];
        const scalar ri = s.radii()[c.i];
        nscd::Vec3 n = c.normal;
        scalar gap = c.gap;
        if (c.j >= 0)
        {
            // grain pair: line of centres at the current positions
            const nscd::Vec3 d = xi - s.positions()[c.j];
            const scalar dn = d.norm();
            if (dn > 0)
            {
                n = d/dn;
                gap = dn - ri - s.radii()[c.j];
            }
        }
        nscd::Vec3 p = xi - (ri + 0.5*gap)*n;
        if (twoD)
        {
            p.z() = grains_.meshPosition(c.i).z();
        }
        const label cell =
            cm.findCell
            (
                overlapMapping::Vec3(p.x(), p.y(), p.z()), cellHint[c.i]
            );
        if (cell >= 0)
        {
            cellHint[c.i] = cell;
            state[k] = psiI[cell] < vapourThreshold_ ? 1 : 0;
        }
        else if (grains_.decomposed())
        {
            elsewhere.append(point(p.x(), p.y(), p.z()));
            elsewhereContact.append(k);
        }
    }
    if (grains_.decomposed())
    {
        // each rank decides its own contacts (those it solves); a point
        // across a processor boundary is looked up where it lies
        labelList got(elsewhere.size(), -1);
        resolveElsewhere(elsewhere, got);
        forAll(got, n)
        {
            state[elsewhereContact[n]] = got[n];
        }
    }
    else if (Pstream::parRun())
    {
        // the same decision on every rank (the grains are advanced
        // identically everywhere): dry if dry where the point was found
        Pstream::listCombineGather(state, maxEqOp<label>());
        Pstream::listCombineScatter(state);
    }

    // several contacts of a grain with one wall (a crease): dry if all are
    // (the table ANDs the flags of a repeated key)
    std::vector<std::uint64_t> keys(nc);
    std::vector<char> dry(nc);
    for (label k = 0; k < nc; ++k)
    {
        keys[k] = pairKeyOfIndices(cs[k].i, cs[k].j);
        dry[k] = state[k] == 1;
    }
    try
    {
        dryPairs_.build(keys, dry);
    }
    catch (const std::invalid_argument& err)
    {
        FatalErrorInFunction
            << err.what() << ": the vapour cohesion keys contact pairs by"
            << " grain ids below 2^31" << exit(FatalError);
    }
    nDryPairs_ = dryPairs_.count(true);
    nWetPairs_ = dryPairs_.count(false);
}


void Foam::vapourCohesion::resolveElsewhere
(
    const UList<point>& points,
    labelList& state
) const
{
    // every rank's points on every rank (few: the contacts whose point
    // lies across a processor boundary), answered where a cell holds them,
    // the answers combined by max (-1: in no rank's cells)
    List<List<point>> all(Pstream::nProcs());
    all[Pstream::myProcNo()] = points;
    Pstream::gatherList(all);
    Pstream::scatterList(all);
    labelList offset(Pstream::nProcs() + 1, 0);
    forAll(all, r)
    {
        offset[r + 1] = offset[r] + all[r].size();
    }
    labelList answer(offset.last(), -1);
    const scalarField& psiI = psi_->primitiveField();
    const overlapMapping::CellMesh& cm = adapter_.cellMesh();
    forAll(all, r)
    {
        if (r == Pstream::myProcNo())
        {
            continue;  // (not in a local cell: asked for that reason)
        }
        forAll(all[r], n)
        {
            const point& x = all[r][n];
            const label cell =
                cm.findCell(overlapMapping::Vec3(x.x(), x.y(), x.z()));
            if (cell >= 0)
            {
                answer[offset[r] + n] = psiI[cell] < vapourThreshold_ ? 1 : 0;
            }
        }
    }
    Pstream::listCombineGather(answer, maxEqOp<label>());
    Pstream::listCombineScatter(answer);
    state.setSize(points.size());
    forAll(points, n)
    {
        state[n] = answer[offset[Pstream::myProcNo()] + n];
    }
}


void Foam::vapourCohesion::report() const
{
    if (!on())
    {
        return;
    }
    // (decomposed: each rank's contacts are its own, summed)
    label nContacts = grains_.system().nContacts();
    label nDry = nDryPairs_, nWet = nWetPairs_;
    if (grains_.decomposed())
    {
        reduce(nContacts, sumOp<label>());
        reduce(nDry, sumOp<label>());
        reduce(nWet, sumOp<label>());
    }
    const label nCohesive = grains_.report().cohesiveContacts;
    Info<< "cohesion: cohesive contacts " << nCohesive << " of " << nContacts;
    scalarList row({scalar(nCohesive), scalar(nContacts)});
    if (byVapour_)
    {
        Info<< ", pairs looked up dry " << nDry << " wet " << nWet;
        row.append(scalarList({scalar(nDry), scalar(nWet)}));
    }
    Info<< endl;
    file_->write(row);
}


// ************************************************************************* //
