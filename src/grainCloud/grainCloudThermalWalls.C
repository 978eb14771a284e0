// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud thermal walls and grain temperatures (see grainCloud.H)

Description
    wallTemperatures (fixed-temperature wall patches [K], the others
    adiabatic: contact conduction with the walls, thesis eq. 4.2),
    frontRearWalls (the 2D Hele-Shaw cell's front and rear walls as a heat
    bath at T_w [K] with relaxation time tau [s]), the heat rate [W] (2D:
    W/m) through each fixed-temperature patch, and the grain temperatures
    [K].

    frontRearWalls: a 2D run has no front and rear walls, but in a
    Hele-Shaw cell (gap l) every grain is within l/2 of them.  With the
    walls at T_w (thermal reservoirs, thesis section 4.3.2) a bed that is
    heated or cooled in the plane relaxes across the gap by conduction: for
    a slab between two walls at T_w with a uniform sink q, the mean
    temperature deficit is q l^2/(12 k_eff), hence per unit bed volume the
    exchange (12 k_eff/l^2)(T_w - T) and for each grain
        Q_i = (m_i c_i/tau)(T_w - T_i),  tau = (rho c)_bed l^2/(12 k_eff),
    (rho c)_bed and k_eff the bed's heat capacity per volume and effective
    conductivity (e.g. Zehner and Schluender 1970; the dropletDigging
    tutorial computes tau).  The same volumetric wall exchange as the
    thesis' eq. 4.14 (q_l = lambda (T_w - T), section 4.2.1) applied to the
    grains; integrated implicitly (nscd::System::setHeatExchange), its heat
    is reported in nscd::StepReport::exchangeHeat (vansFoam's heat budget:
    "grain walls").  Errors (FatalIOError): 3D mesh, tau <= 0, T_w <= 0,
    unknown keyword, no material with heatCapacity.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "grainDictionaryTools.H"

#include <cmath>
#include <utility>

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

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
    const HashTable<scalar> Tpatch
    (
        grainTools::patchValues(wt, patches, "temperature [K]", 0)
    );
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


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

bool Foam::grainCloud::heatOn() const
{
    bool on = false;
    for (const int m : system_->materials())
    {
        if (system_->material(m).heatCapacity > 0)
        {
            on = true;
            break;
        }
    }
    // decomposed: a rank may hold no grain (the same answer on every rank)
    return decomposed_ ? returnReduce(on, orOp<bool>()) : on;
}


Foam::scalar Foam::grainCloud::meanTemperature(const bool integratedOnly) const
{
    scalar s = 0;
    label n = 0;
    for (std::size_t i = 0; i < system_->size(); ++i)
    {
        if
        (
            owned(i)
         && (
                !integratedOnly
             || (
                    system_->material(system_->materials()[i]).heatCapacity > 0
                 && !system_->fixedTemperature(i)
                )
            )
        )
        {
            s += system_->temperatures()[i];
            ++n;
        }
    }
    if (decomposed_)
    {
        reduce(s, sumOp<scalar>());
        reduce(n, sumOp<label>());
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
    // from the contacts and temperatures after the last (sub-)step: exact
    // for the last sub-step; with several sub-steps per time step the
    // sub-step length is taken as dt/substeps
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
        // decomposed: a grain-wall contact conducts on the grain's owner
        if
        (
            owned(i)
         && system_->material(system_->materials()[i]).heatCapacity > 0
         && !system_->fixedTemperature(i)
        )
        {
            const scalar H = system_->contactConductance(c, dtSub);
            rates[iter.val()].second += H*(system_->wallTemperature(w) - T[i]);
        }
    }
    if (decomposed_)
    {
        for (auto& r : rates)
        {
            reduce(r.second, sumOp<scalar>());
        }
    }
    return rates;
}

// ************************************************************************* //
