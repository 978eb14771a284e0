// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::Subdomain: the step of one subdomain of a decomposed grain system
// (Subdomain.H): the stages of System::step (System::Impl::runStages,
// Step.cpp) with the decomposed work at their hooks (DecomposedStages: the
// contacts this subdomain owns, copy masses for the interface grains, the
// interface-averaged solve of SubdomainSolve.cpp, decisions taken together,
// the heat step of SubdomainHeat.cpp); the grain rows of migrations and ghosts.
#include "nscd/Subdomain.H"

#include "StepHooks.H"
#include "SubdomainHeat.H"
#include "SubdomainSolve.H"
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>
#include <string>

namespace nscd
{

Subdomain::Subdomain(System& system, SubdomainCoupling& coupling)
    : sys_(system), coupling_(coupling), scratch_(std::make_unique<Scratch>()),
      interface_(std::make_unique<InterfaceImpulses>())
{
}

Subdomain::~Subdomain() = default;

std::size_t Subdomain::rowBytes(unsigned flags) const { return sys_.impl_->columns.rowBytes(flags); }

void Subdomain::packGrain(std::size_t i, unsigned flags, char* out) const
{
    sys_.impl_->columns.packRow(i, flags, out);
}

void Subdomain::unpackGrain(std::size_t i, unsigned flags, const char* in)
{
    System::Impl& I = *sys_.impl_;
    I.columns.unpackRow(i, flags, in);
    if (!std::isfinite(I.rad[i]) || !(I.rad[i] > 0) || I.mat[i] < 0 || I.mat[i] >= int(I.materials.size()))
        throw InputError("nscd::Subdomain::unpackGrain: grain " + std::to_string(i) + ": radius "
                         + std::to_string(I.rad[i]) + ", material " + std::to_string(I.mat[i]) + " of "
                         + std::to_string(I.materials.size()) + " (a row packed with other columns?)");
    I.setMassInertia(i);
}

std::size_t Subdomain::addGrain(unsigned flags, const char* in)
{
    // the grain comes with its id (setGrainId): the system's next id is
    // not advanced, so that a decomposed system's nextGrainId stays that
    // of the whole system, however many ghosts a rank adds
    const long next = sys_.impl_->nextId;
    const std::size_t i = sys_.impl_->appendRow();
    sys_.impl_->nextId = next;
    try
    {
        unpackGrain(i, flags, in);
    }
    catch (const InputError&)
    {
        sys_.removeGrains({i});
        throw;
    }
    return i;
}

System Subdomain::withoutGrains(const System& s)
{
    System out(s.dimension());
    *out.impl_ = *s.impl_;
    std::vector<std::size_t> all(out.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    out.removeGrains(all);
    return out;
}

void Subdomain::setGrainId(std::size_t i, long id)
{
    if (id < 0) throw InputError("nscd::Subdomain::setGrainId: negative grain id " + std::to_string(id));
    System::Impl& I = *sys_.impl_;
    I.ids.at(i) = id;
    I.nextId = std::max(I.nextId, id + 1);
}

namespace
{
/**
 * The input checks of Subdomain::step, collective: if one subdomain refuses
 * the step, all do (none is left waiting in a collective of the step).
 * @return true if some temperature is integrated here (heatCheck).
 */
bool checkStep(System::Impl& I, SubdomainCoupling& coupling, double dt, const std::vector<char>& owned,
               const std::vector<long>& globalId)
{
    const int N = int(I.x.size());
    std::string refused;
    bool heat = false;
    try
    {
        if (owned.size() != std::size_t(N) || globalId.size() != std::size_t(N))
            throw InputError("nscd::Subdomain::step: owned and globalId need one entry per grain ("
                             + std::to_string(N) + "), got " + std::to_string(owned.size()) + " and "
                             + std::to_string(globalId.size()));
        if (!(dt > 0) || !std::isfinite(dt))
            throw InputError("nscd::Subdomain::step: dt must be > 0, got " + std::to_string(dt));
        for (const System::Droplet& d : I.droplets) checkDroplet(d, "nscd::Subdomain::step");
        System::Impl::checkSettings(I.settings, "nscd::Subdomain::step");
        I.checkComplianceMethod("nscd::Subdomain::step");
        if (I.settings.method != System::Settings::Method::NLGS || I.settings.relaxation != 1.0)
        {
            static const char* const methods[] = {"NLGS", "OverRelaxedNLGS", "APGD", "NNCG", "Newton"};
            const int m = int(I.settings.method);
            throw InputError(
                "nscd::Subdomain::step: decomposed grains are solved by plain NLGS (method NLGS, "
                "relaxation 1: its sweeps alternate with the averaging of the interface grains), "
                "got method "
                + std::string(m >= 0 && m < 5 ? methods[m] : "?") + ", relaxation "
                + std::to_string(I.settings.relaxation) + "; use NLGS with relaxation 1");
        }
        if (I.settings.convergence != System::Settings::Convergence::Max)
            throw InputError("nscd::Subdomain::step: the RMS convergence test is not available with "
                             "decomposed grains (its interface averaging stops on the Max test); use Max");
        heat = I.heatCheck();
    }
    catch (const InputError& e)
    {
        refused = e.what();
    }
    if (coupling.maxOverSubdomains(refused.empty() ? 0.0 : 1.0) > 0)
        throw InputError(refused.empty() ? "nscd::Subdomain::step: another subdomain refused the step"
                                           " (its error names the input)"
                                         : refused);
    return heat;
}

/**
 * The decomposed step's work at the stages of System::Impl::runStages: the
 * contacts this subdomain owns, the copy masses of the interface bodies,
 * the interface warm start, the interface-averaged solve, the decisions
 * taken together, the interface grains' drag and the droplets' impulses
 * summed over the subdomains, the interface impulses kept for the next
 * step, and the heat step of the owned grains. No energy limit of a
 * capped solve (Subdomain.H).
 */
class DecomposedStages : public System::Impl::StepHooks
{
public:
    DecomposedStages(System::Impl& I, SubdomainCoupling& coupling, Subdomain::Scratch& scratch,
                     Subdomain::InterfaceImpulses& last, const std::vector<char>& owned,
                     const std::vector<long>& globalId, double dt)
        : StepHooks(I), C(coupling), X(scratch), last(last), owned(owned), globalId(globalId),
          N(int(I.x.size())), NW(int(I.walls.size())), ND(int(I.droplets.size())),
          warmScale(I.settings.warmStart && I.lastDt > 0 ? dt / I.lastDt : 0.0)
    {
        X.dropletBodies.clear();
        for (int k = 0; k < ND; ++k)
            if (I.droplets[k].mass > 0) X.dropletBodies.push_back(N + NW + k);
        // the tolerance scale d_min of the undecomposed system (collective;
        // no grain anywhere, e.g. all left through an outlet: 0, as rMin of
        // an empty system, not 2e300, whose square overflows)
        const double m = C.maxOverSubdomains(N > 0 ? -I.rMin() : -1e300);
        dmin = m > -1e300 ? -2 * m : 0.0;
        X.inContact.resize(N);
    }

    /// The undecomposed system's tolerance scale d_min (twice its r_min).
    double dmin = 0;

    /// The contacts this subdomain owns: the owner of the grain with the
    /// smaller global id solves a grain pair, the grain's owner a wall or
    /// droplet contact; their grains flagged in inContact (one pass over the
    /// contacts, which are memory-bound), the droplets in dropletShared.
    int ownContacts(int NC0) override
    {
        std::vector<Contact>& Cs = I.newContacts;
        std::fill(X.inContact.begin(), X.inContact.end(), 0);
        X.dropletShared.assign(ND, 0);
        std::size_t m = 0;
        auto keep = [&](std::size_t from, std::size_t to, bool droplets)
        {
            for (std::size_t k = from; k < to; ++k)
            {
                const Contact& c = Cs[k];
                const int gi = I.order[c.i];
                const int gj = !droplets && c.j < N ? I.order[c.j] : -1;
                if (!owned[gj < 0 || globalId[gi] < globalId[gj] ? gi : gj]) continue;
                X.inContact[gi] = 1;
                if (gj >= 0) X.inContact[gj] = 1;
                if (droplets) X.dropletShared[c.j - N - NW] = 1;
                if (m != k) Cs[m] = c;
                ++m;
            }
        };
        keep(0, std::size_t(NC0), false);
        const int kept = int(m);
        keep(std::size_t(NC0), Cs.size(), true);
        Cs.resize(m);
        return kept;
    }

    /// The interface grains' masses shared among their copies (m/n, J/n for
    /// n copies); a droplet with mass: a copy of mass m/n on each of the n
    /// subdomains that solve one of its contacts.
    void shareMasses() override
    {
        std::vector<int>& copies = X.copies;
        C.countCopies(X.inContact, copies);
        for (int i = 0; i < N; ++i)
        {
            if (!(owned[i] || X.inContact[i]) || copies[i] <= 1) continue;
            Body& B = I.body[I.slotOf[i]];
            B.im *= copies[i];
            B.im0 *= copies[i];
            B.ii *= copies[i];
        }
        for (int b : X.dropletBodies)
        {
            const double n = C.sumOverSubdomains(X.dropletShared[b - N - NW] ? 1.0 : 0.0);
            if (!X.dropletShared[b - N - NW] || !(n > 1)) continue;
            I.body[b].im *= n;
            I.body[b].im0 *= n;
        }
    }

    void warmStartInterface() override
    {
        nscd::warmStartInterface(I, C, X, owned, globalId, last, warmScale);
    }

    /// The interface-averaged solve; rep's solver fields as solveContacts
    /// sets them (the contacts: the most of the step's solves).
    void solve(double dt, StepReport& rep, const std::vector<int>* seed) override
    {
        StepReport r;
        solveDecomposed(I, C, X, dt, dmin, r, seed);
        rep.contacts = std::max(rep.contacts, r.contacts);
        rep.localSolves = r.localSolves;
        rep.sweeps = r.sweeps;
        rep.residual = r.residual;
        rep.converged = r.converged;
    }

    bool any(bool flag) override { return C.maxOverSubdomains(flag ? 1.0 : 0.0) > 0; }

    void limitEnergy(double, StepReport&) override {}

    /// integrate, with the drag impulse of an interface grain from its whole
    /// contact impulse (its copies' contacts here and elsewhere: n (local +
    /// interface)) and a droplet's impulse from the contacts of every
    /// subdomain.
    void integrate(double dt, int NC0) override
    {
        X.dragTerms.resize(X.iface.size());
        for (std::size_t k = 0; k < X.iface.size(); ++k)
            X.dragTerms[k] = {X.iface[k], X.copies[X.iface[k]], X.lambda[2 * k]};
        I.dragInterface = &X.dragTerms;
        std::vector<Vec3> dropletImpulse0(ND);
        for (int k = 0; k < ND; ++k) dropletImpulse0[k] = I.droplets[k].impulse;
        I.integrate(dt, NC0);
        for (int k = 0; k < ND; ++k)
        {
            Vec3& J = I.droplets[k].impulse;
            const Vec3 dJ = J - dropletImpulse0[k];
            for (int c = 0; c < 3; ++c) J[c] = dropletImpulse0[k][c] + C.sumOverSubdomains(dJ[c]);
        }
        I.dragInterface = nullptr;
    }

    /// storeImpulses, and the interface impulses kept for the next step.
    void storeImpulses(double dt, int NC0, StepReport& rep) override
    {
        I.storeImpulses(dt, NC0, rep);
        keepInterface(X, globalId, last);
    }

    void heat(double dt, StepReport& rep) override { decomposedHeatStep(I, C, owned, dt, rep); }

private:
    SubdomainCoupling& C;
    Subdomain::Scratch& X;
    Subdomain::InterfaceImpulses& last;
    const std::vector<char>& owned;
    const std::vector<long>& globalId;
    const int N, NW, ND;
    const double warmScale; ///< dt/lastDt of the warm start (0: none)
};
} // namespace

StepReport Subdomain::step(double dt, const std::vector<char>& owned, const std::vector<long>& globalId)
{
    System::Impl& I = *sys_.impl_;
    const bool heat = checkStep(I, coupling_, dt, owned, globalId);
    for (System::Droplet& d : I.droplets)
        if (d.grainImpulse.size() != I.x.size()) d.grainImpulse.assign(I.x.size(), 0.0);
    DecomposedStages stages(I, coupling_, *scratch_, *interface_, owned, globalId, dt);
    StepReport rep;
    rep.method = int(System::Settings::Method::NLGS);
    // the lengths scaled by r_min are the undecomposed system's for the
    // step (System::Impl::rMinOfStep), restored however the step ends
    I.runStages(dt, 0.5 * stages.dmin, heat, rep, stages);
    return rep;
}

} // namespace nscd
