// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet restart and output (see vapourDroplet.H)

Description
    The restart file <time>/uniform/droplet (droplet state, the step of
    the grain predictor's history, film heat and heat-sink directions),
    read at the start and written with the fields at every write (the
    scheduled ones, the last step, a stop signal: vapourDropletRestartFile);
    the predictor's per-grain history as restart columns of the grain
    state (attach; a file written before holds it as per-grain lists,
    still read); and the per-step line of
    postProcessing/droplet/<startTime>/droplet.dat.
\*---------------------------------------------------------------------------*/

#include "vapourDroplet.H"
#include "vansCloud.H"

#include <sstream>

// * * * * * * * * * * * * * * * * Local helpers * * * * * * * * * * * * * * //

namespace
{

//- Two lists of the restart dictionary d that go together (one entry per
//  grain or cell): FatalIOError naming both if their sizes differ
template<class TypeA, class TypeB>
void readListPair
(
    const Foam::dictionary& d,
    const Foam::word& nameA,
    const Foam::word& nameB,
    Foam::List<TypeA>& a,
    Foam::List<TypeB>& b
)
{
    a = d.get<Foam::List<TypeA>>(nameA);
    b = d.get<Foam::List<TypeB>>(nameB);
    if (a.size() != b.size())
    {
        FatalIOErrorInFunction(d)
            << nameA << " (" << a.size() << ") and " << nameB << " ("
            << b.size() << ") differ in size in " << d.name() << Foam::nl
            << "    Fix: restart from an unedited write time, or delete both"
            << " entries." << Foam::exit(Foam::FatalIOError);
    }
}

} // End anonymous namespace


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vapourDroplet::readRestart()
{
    IOobject io
    (
        "droplet", mesh_.time().timeName(), "uniform", mesh_,
        IOobject::MUST_READ, IOobject::NO_WRITE, false
    );
    if (!io.typeHeaderOk<IOdictionary>(true))
    {
        if (mesh_.time().timeIndex() > 0 || mesh_.time().value() > 0)
        {
            Info<< "vapourDroplet: no " << mesh_.time().timeName()
                << "/uniform/droplet: the droplet starts as"
                << " constant/dropletProperties gives it" << nl;
        }
        return;
    }
    const IOdictionary d(io);
    x_ = d.get<vector>("centre");
    u_ = d.get<vector>("velocity");
    m_ = d.get<scalar>("mass");
    y0_ = d.get<scalar>("y0");
    mdot_ = d.get<scalar>("mdot");
    pendingVapour_ = d.get<scalar>("pendingVapour");
    Vp_ = d.get<scalar>("grainVolume");
    if (d.found("grainHistory"))
    {
        restartHistory_ = d.subDict("grainHistory");
    }
    if (film_ && d.found("filmHeat"))
    {
        readListPair(d, "filmGrain", "filmHeat", filmGrain_, filmHeat_);
    }
    if (grainRelease_ && d.found("gasHeat"))
    {
        Qf_ = d.get<scalar>("gasHeat");
    }
    if (localRelease_ && d.found("sinkHeat"))
    {
        readListPair(d, "sinkDirection", "sinkHeat", sinkDirection_, sinkHeat_);
    }
    Info<< "vapourDroplet: restart from " << d.objectPath() << endl;
}


void Foam::vapourDroplet::attach(vansCloud& cloud)
{
    cloud_ = &cloud;
    if (grainRelease_)
    {
        // each grain's heat of the last step, following the grains and
        // written with them (a start state without it: no grain vapour in
        // the first step, the gas's share in the ring); decomposed: carried
        // with a grain that changes rank and copied to its ghosts, whose
        // overlaps release it in this rank's cells
        cloud.grains().addStartColumn<scalar>
        (
            grainVapourColumn,
            nscd::ColumnMigrate | nscd::ColumnGhost,
            scalar(0)
        );
    }
    if (grainDrag_ && drag_.valid())
    {
        declareGrainHistory();
    }
}


void Foam::vapourDroplet::declareGrainHistory()
{
    grainCloud& grains = cloud_->grains();
    bool read = true;
    // decomposed grains: carried with a grain that changes rank and copied
    // to its ghosts, so that every copy predicts the same force
    for (const word& name : historyColumns)
    {
        read =
            grains.addStartColumn<vector>
            (
                name, nscd::ColumnMigrate | nscd::ColumnGhost, Zero
            )
         && read;
    }
    if (restartHistory_.empty() || restartHistory_.found("grains"))
    {
        return;     // none, or per-grain lists: restoreGrainHistory
    }
    const dictionary h(restartHistory_);
    restartHistory_.clear();
    if (!read)
    {
        FatalIOErrorInFunction(h)
            << "grainHistory of the droplet restart file needs the grain"
            << " columns " << FixedList<word, 4>(historyColumns)
            << " in the grain state of time " << mesh_.time().timeName()
            << ", which lacks them." << nl
            << "    Fix: restart from a time written by the same case"
            << " (uniform/droplet with its grainState.h5), or delete"
            << " grainHistory from <time>/uniform/droplet (the first step"
            << " then runs without the contact predictor)."
            << exit(FatalIOError);
    }
    history_ = true;
    history2_ = h.get<bool>("second");
    prevDt_ = h.get<scalar>("dt");
}


void Foam::vapourDroplet::restoreGrainHistory(const nscd::System& sys)
{
    const dictionary h(restartHistory_);
    restartHistory_.clear();
    if (cloud_->grains().decomposed())
    {
        FatalIOErrorInFunction(h)
            << "grainHistory of the droplet restart file lists per-grain"
            << " values by grain index (a file written before the history"
            << " became grainState.h5 columns), which decomposed grains"
            << " cannot follow." << nl
            << "    Fix: restart with grainDecomposition replicated; in"
            << " constant/grainProperties and write once, or delete"
            << " grainHistory from <time>/uniform/droplet (the first step"
            << " then runs without the contact predictor)."
            << exit(FatalIOError);
    }
    const label n = sys.size();
    const labelList grains(h.get<labelList>("grains"));
    const List<vector> v1(h.get<List<vector>>("velocity"));
    const List<vector> F1(h.get<List<vector>>("force"));
    const bool second = h.found("velocity2");
    const List<vector> v2(second ? h.get<List<vector>>("velocity2") : v1);
    const List<vector> dG
    (
        second
      ? h.get<List<vector>>("gasForceChange")
      : List<vector>(v1.size(), Zero)
    );
    if
    (
        v1.size() != grains.size() || F1.size() != grains.size()
     || v2.size() != grains.size() || dG.size() != grains.size()
     || (grains.size() && (min(grains) < 0 || max(grains) >= n))
    )
    {
        FatalIOErrorInFunction(h)
            << "grainHistory of the droplet restart file does not match the "
            << n << " grains of the restarted case (list sizes or grain"
            << " labels)." << nl
            << "    Fix: restart from a time written by the same case, or"
            << " delete grainHistory from <time>/uniform/droplet (the first"
            << " step then runs without the contact predictor)."
            << exit(FatalIOError);
    }
    const auto& vel = sys.velocities();
    const bool twoD = adapter_.twoD();
    UList<vector> prevVelocity(history(0));
    UList<vector> prevForce(history(1));
    UList<vector> prevVelocity2(history(2));
    UList<vector> gasForceChange(history(3));
    forAll(prevVelocity, g)
    {
        prevVelocity[g] =
            vector(vel[g][0], vel[g][1], twoD ? 0.0 : vel[g][2]);
    }
    prevVelocity2.deepCopy(prevVelocity);
    prevForce = Zero;
    gasForceChange = Zero;
    forAll(grains, j)
    {
        prevVelocity[grains[j]] = v1[j];
        prevVelocity2[grains[j]] = v2[j];
        prevForce[grains[j]] = F1[j];
        gasForceChange[grains[j]] = dG[j];
    }
    history_ = true;
    history2_ = second;
    prevDt_ = h.get<scalar>("dt");
}


void Foam::vapourDroplet::writeRestart(Ostream& os) const
{
    dictionary d;
    d.add("centre", x_);
    d.add("velocity", u_);
    d.add("mass", m_);
    d.add("y0", y0_);
    d.add("mdot", mdot_);
    d.add("pendingVapour", pendingVapour_);
    d.add("grainVolume", Vp_);
    if (film_)
    {
        d.add("filmGrain", filmGrain_);
        d.add("filmHeat", filmHeat_);
    }
    if (grainRelease_)
    {
        d.add("gasHeat", Qf_);      // the gas's share of the last step
    }
    if (localRelease_)
    {
        d.add("sinkDirection", sinkDirection_);
        d.add("sinkHeat", sinkHeat_);
    }
    // the predictor's step and whether it has a second step (its per-grain
    // values: columns of grainState.h5, vapourDroplet.H historyColumns)
    if (history_ && prevDt_ > 0 && cloud_ && historyGrains_)
    {
        dictionary h;
        h.add("dt", prevDt_);
        h.add("second", history2_);
        d.add("grainHistory", h);
    }
    d.writeEntries(os);
}


void Foam::vapourDroplet::finishStep()
{
    const Time& runTime = mesh_.time();
    if (Pstream::master())
    {
        if (!datPtr_.valid())
        {
            const fileName dir
            (
                runTime.globalPath()/"postProcessing"/"droplet"
               /runTime.timeName(runTime.startTime().value())
            );
            mkDir(dir);
            datPtr_.reset(new OFstream(dir/"droplet.dat"));
            datPtr_() << "# vapourDroplet (thesis eq. 4.15-4.17), SI units";
            if (adapter_.twoD())
            {
                datPtr_() << ", m/mdot/Q/Vdot over the mesh depth "
                    << adapter_.depth() << " m";
            }
            datPtr_() << nl
                << "# time x y u v m mdot Q_f Q_p R depth Vdot V_p"
                   " Fp_x Fp_y Fpen_x Fpen_y nGrainsIn Fw_x Fw_y S_x S_y"
                   " Fc_x Fc_y Q_film Fg_x Fg_y Fg_z"
                << nl;
        }
        // the force of the droplet on the grains, summed (the log's
        // "droplet-grain force" line, fv::vapourDropletSource)
        const vector& Fg = grainForceTotal_;
        std::ostringstream os;
        os.precision(16);
        os  << runTime.value() << ' ' << x_.x() << ' ' << x_.y() << ' '
            << u_.x() << ' ' << u_.y() << ' ' << m_ << ' ' << mdot_ << ' '
            << Qf_ << ' ' << Qp_ << ' ' << radius() << ' ' << y0_ - x_.y()
            << ' ' << Vdot_ << ' ' << Vp_ << ' ' << Fp_.x() << ' '
            << Fp_.y() << ' ' << Ff_.x() << ' ' << Ff_.y() << ' '
            << nGrainsIn_ << ' ' << Fw_.x() << ' ' << Fw_.y() << ' '
            << S_.x() << ' ' << S_.y() << ' ' << Fc_.x() << ' ' << Fc_.y()
            << ' ' << Qfilm_ << ' ' << Fg.x() << ' ' << Fg.y() << ' '
            << Fg.z();
        datPtr_() << os.str().c_str() << nl;
        datPtr_().flush();
    }
}


// * * * * * * * * * * * * * * vapourDropletRestartFile * * * * * * * * * * * //

Foam::vapourDropletRestartFile::vapourDropletRestartFile
(
    const fvMesh& mesh,
    const vapourDroplet& droplet
)
:
    regIOobject
    (
        IOobject
        (
            "droplet", mesh.time().timeName(), "uniform", mesh,
            IOobject::NO_READ, IOobject::AUTO_WRITE
        )
    ),
    droplet_(droplet)
{}


const Foam::word& Foam::vapourDropletRestartFile::type() const
{
    return IOdictionary::typeName;
}


bool Foam::vapourDropletRestartFile::writeData(Ostream& os) const
{
    droplet_.writeRestart(os);
    return os.good();
}

// ************************************************************************* //
