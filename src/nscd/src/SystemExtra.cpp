// SPDX-License-Identifier: GPL-3.0-or-later
// Sub-stepping (advance), the reach check of the re-detection of grains
// that leave their reach (raiseReaches), checks, contact views, conductance.
#include "ContactLaws.H"
#include "SystemImpl.H"
#include "nscd/ComplianceStepScope.H"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>

namespace nscd
{

namespace
{
/// Displacement bound per (sub-)step, in d_min, of a body at its free
/// velocity (advance(): only for absurd velocities, see System.H).
constexpr double maxTravelDiameters = 100;

/// The bodies that set the sub-step of advance() over dt: the largest
/// change of a body's velocity over dt from the forces of the step,
/// |v_free - v| + r |w_free - w| (free velocities of freeVelocities: gravity,
/// external force and torque, droplet forces); the largest tangential
/// relative free velocity |(1 - n n)(v_free,i - v_free,j)| of two
/// touching grains (gap <= alertMargin r_min, contacts of the last
/// step); and the largest free speed |v_free| + r |w_free| (walls: their
/// velocity); who: grain id >= 0, -1 wall, -2 droplet, -3 nothing
/// moves. Fills Impl::body.
struct Fastest
{
    double dv = 0, vt = 0, v = 0;
    int whoDv = -3, whoVt = -3, whoV = -3;
};

template <class ImplT>
Fastest fastest(ImplT& I, double dt)
{
    Fastest f;
    I.syncKeptContacts(); // the contacts of the last step, after grains were added
    I.freeVelocities(dt);
    const int N = int(I.x.size()), NW = int(I.walls.size());
    for (int i = 0; i < N; ++i) // by grain (bodies by slot)
    {
        const Body& B = I.body[I.slotOf[i]];
        const double s = B.v.norm() + B.r * B.w.norm();
        Vec3 v0 = I.v[i], w0 = I.w[i];
        if (I.dim == 2)
        {
            v0.z() = 0;
            w0.x() = w0.y() = 0;
        }
        const double dv = (B.v - v0).norm() + B.r * (B.w - w0).norm();
        // std::isfinite first: comparing a NaN raises FE_INVALID (SIGFPE when trapped)
        if (!std::isfinite(s) || !std::isfinite(dv))
        {
            f.v = f.dv = s + dv;
            f.whoV = f.whoDv = i;
            return f;
        }
        if (s > f.v)
        {
            f.v = s;
            f.whoV = i;
        }
        if (dv > f.dv)
        {
            f.dv = dv;
            f.whoDv = i;
        }
    }
    const double touch = I.settings.alertMargin * I.rMin();
    for (const Contact& c : I.contacts)
    {
        if (c.j >= N) continue; // walls: plane faces keep their normal
        // contacts by slot: centres and radii of the packed records
        // (filled by freeVelocities above)
        const GrainSlot& A = I.packed[c.i];
        const GrainSlot& B = I.packed[c.j];
        const Vec3 d = A.x - B.x;
        const double dn = d.norm();
        if (!(dn - A.r - B.r <= touch) || !(dn > 0)) continue;
        const Vec3 n = d / dn;
        const Vec3 u = I.body[c.i].v - I.body[c.j].v;
        const double vt = (u - u.dot(n) * n).norm();
        if (vt > f.vt)
        {
            f.vt = vt;
            f.whoVt = I.order[c.i];
        }
    }
    for (const auto& W : I.walls)
        if (W.velocity.norm() > f.v)
        {
            f.v = W.velocity.norm();
            f.whoV = -1;
        }
    for (int k = 0; k < int(I.droplets.size()); ++k)
    {
        const Vec3& v = I.body[N + NW + k].v;
        const double dv = (v - I.droplets[k].velocity).norm();
        if (v.norm() > f.v)
        {
            f.v = v.norm();
            f.whoV = -2;
        }
        if (dv > f.dv)
        {
            f.dv = dv;
            f.whoDv = -2;
        }
    }
    return f;
}

/// Sub-step count over dt (see System::advance) and its cause (0: the
/// velocity change, 1: the tangential motion of touching grains, 2: the
/// travel): the velocity change of the step and the tangential relative
/// velocity of touching grains move a body at most fraction d_min per
/// sub-step, the free velocity at most maxTravelDiameters d_min.
template <class ImplT>
double subStepsOf(const ImplT& I, double dt, double fraction, const Fastest& f, int* cause = nullptr)
{
    const double dmin = 2 * I.rMin();
    if (dmin == 0) return 1;
    const double a[3] = {f.dv * dt / (fraction * dmin), f.vt * dt / (fraction * dmin),
                         f.v * dt / (maxTravelDiameters * dmin)};
    const int k = int(std::max_element(a, a + 3) - a);
    if (cause) *cause = k;
    return std::max(1.0, std::ceil(a[k] * (1 - 1e-12))); // guard round-off
}

/// The body that rule k of subStepsOf (0 velocity change, 1 tangential
/// slide, 2 travel) measured (who: grain index, -1 wall, -2 droplet, -3
/// nothing moves) and its speed [m/s].
struct RuleBody
{
    int who;
    double speed;
};
RuleBody ruleBody(int k, const Fastest& f)
{
    return k == 0 ? RuleBody{f.whoDv, f.dv} : (k == 1 ? RuleBody{f.whoVt, f.vt} : RuleBody{f.whoV, f.v});
}

/// The cause, body (a grain by its id, System::grainIds) and speed of rule
/// k of subStepsOf for the count n (None when n = 1).
template <class ImplT>
SubStepChoice choiceOf(const ImplT& I, double n, int k, const Fastest& f)
{
    SubStepChoice c;
    c.count = n;
    if (n <= 1) return c;
    using Cause = StepReport::SubStepCause;
    c.cause = k == 0 ? Cause::VelocityChange : (k == 1 ? Cause::TangentialSlide : Cause::Travel);
    const RuleBody b = ruleBody(k, f);
    c.body = b.who >= 0 ? I.ids[std::size_t(b.who)] : long(b.who);
    c.speed = b.speed;
    return c;
}
} // namespace

double System::subStep(double dt, double fraction) const { return dt / subStepChoice(dt, fraction).count; }

SubStepChoice System::subStepChoice(double dt, double fraction) const
{
    if (!(dt > 0)) throw InputError("nscd::System::subStep: dt must be > 0");
    if (!(fraction > 0)) throw InputError("nscd::System::subStep: fraction must be > 0");
    Impl& I = *impl_; // fastest() fills the work array body only
    const Fastest f = fastest(I, dt);
    int cause = 0;
    const double n = subStepsOf(I, dt, fraction, f, &cause);
    return choiceOf(I, n, cause, f);
}

// The sub-step rules of advance (System.H), and why. Contacts are detected
// per pair from each body's own reach (Settings::alertDistanceFactor) and
// the gap law keeps every grain out of the others and of the walls whatever
// its displacement in the step (see step()), so a fast grain needs no
// sub-steps and does not make the others sub-step (the former rule of thesis
// section 5.1.3, |v_max| dt_sub <= fraction * d_min for all grains, is not
// needed for contacts). The velocity-change rule keeps the accuracy of the
// former rule for the first-order integration of a strongly forced grain
// (e.g. a grain falling from rest over a long step). The tangential rule:
// the gap law holds each contact on its tangent plane at the step start, so
// grains moving around each other by a large part of a diameter in one step
// would be held apart and a dense flow slowed, enough to change the regime
// of a granular collapse into water (test_granularCollapse.py). The 100 d_min
// rule: the detection of a fast grain scans the grid cells its alert sphere
// covers.
StepReport System::advance(double dt, double fraction)
{
    if (!(dt > 0)) throw InputError("nscd::System::advance: dt must be > 0");
    if (!(fraction > 0)) throw InputError("nscd::System::advance: fraction must be > 0");
    Impl& I = *impl_;
    const long maxSub = I.settings.maxSubSteps;
    if (maxSub < 1) throw InputError("nscd::System::advance: maxSubSteps must be >= 1");
    StepReport total;
    double remaining = dt;
    const ComplianceStepScope lawStep(*this, dt); // the sub-steps keep relativeCompliance's law of dt
    using clock = std::chrono::steady_clock;
    clock::time_point lastBeat = clock::now();
    const auto beatEvery = std::chrono::duration<double>(I.settings.heartbeatSeconds);
    while (remaining > 0)
    {
        // velocity change over the whole dt of the call (not the remaining
        // time): constant forces give equal sub-steps
        const Fastest f = fastest(I, dt);
        if (!std::isfinite(f.v) || !std::isfinite(f.dv)) // (f.vt is then finite or NaN-free: same velocities)
        {
            std::ostringstream os;
            os << "nscd::System::advance: grain " << f.whoV << " has a non-finite velocity, force or"
               << " torque at the start of a sub-step (force " << I.force[f.whoV].transpose()
               << " N, velocity " << I.v[f.whoV].transpose() << " m/s)";
            throw StepError(os.str());
        }
        int cause = 0;
        const double n = subStepsOf(I, dt, fraction, f, &cause);
        double h = std::min(remaining, dt / n);
        if (h >= remaining * (1 - 1e-12)) h = remaining;
        const double needed = total.substeps + std::ceil(remaining / h * (1 - 1e-12));
        if (needed > double(maxSub))
        {
            const double dmin = 2 * I.rMin();
            const RuleBody b = ruleBody(cause, f);
            const int who = b.who;
            const double val = b.speed;
            std::ostringstream os;
            os << "nscd::System::advance: the step of " << dt << " s needs about " << needed
               << " sub-steps, more than maxSubSteps = " << maxSub << " (";
            if (who >= 0)
            {
                if (cause == 0)
                    os << "the forces of the step change the velocity of grain " << who << " by " << val
                       << " m/s, external force " << I.force[who].norm() << " N";
                else if (cause == 1)
                    os << "grain " << who << " slides or rolls past a touching grain at " << val << " m/s";
                else
                    os << "grain " << who << " moves at " << val << " m/s";
                if (cause != 1 && I.g.norm() > 0)
                    os << " (" << I.force[who].norm() / (I.mass[who] * I.g.norm()) << " x its weight)";
            }
            else
                os << (who == -1 ? "a wall" : "a droplet")
                   << (cause == 0 ? " changes its velocity by " : " moves at ") << val << " m/s";
            if (cause == 2)
                os << "; a grain may move by " << maxTravelDiameters
                   << " d_min = " << maxTravelDiameters * dmin << " m per sub-step)";
            else
                os << "; this may move a grain by " << fraction << " d_min = " << fraction * dmin
                   << " m per sub-step)";
            throw StepError(os.str());
        }
        if (total.substeps == 0)
        {
            const SubStepChoice c = choiceOf(I, n, cause, f);
            total.substepCause = c.cause;
            total.substepBody = c.body;
            total.substepSpeed = c.speed;
        }
        const StepReport r = step(h);
        remaining = (h == remaining) ? 0.0 : remaining - h;
        if (I.settings.heartbeat && remaining > 0 && clock::now() - lastBeat >= beatEvery)
        {
            I.settings.heartbeat(total.substeps + 1, total.substeps + 1 + remaining / h);
            lastBeat = clock::now();
        }
        total.addSubStep(r);
    }
    return total;
}

bool System::Impl::raiseReaches(double dt)
{
    const int N = int(x.size());
    if (N == 0) return false;
    const double af = settings.alertDistanceFactor;
    const double free = 0.5 * settings.alertMargin * rMin();
    bool any = false;
    for (int i = 0; i < N; ++i) // slots
    {
        if (packed[i].fix) continue;
        const Body& B = body[i];
        const double vn = B.v.norm();
        if (!(vn * dt > af * dt * speed[i] + free)) continue;
        if (reachFloor.empty()) reachFloor.assign(N, 0.0);
        reachFloor[i] = std::max(reachFloor[i], vn + B.r * B.w.norm());
        any = true;
    }
    return any;
}

namespace
{

/// Key of a grain pair (i, j >= 0) or of a grain and a wall (j < 0).
long long pairKey(int i, int j) { return (static_cast<long long>(i) << 32) | static_cast<std::uint32_t>(j); }

} // namespace

// The overlap [m] each loaded compliant contact of the state's contact
// list carries under its impulse: at rest the compliant law holds the gap
// at g = -eps dt r_n (CompliantSignorini, eps = c/dt^2 + beta W_nn (T/dt)^2), so a
// state the solver left loaded (a restart, a settled bed written with its
// contact impulses) has overlaps of that size. Keyed by pairKey(i, j),
// grains i < j or a wall j < 0; empty without a compliant material or a
// step's impulses.
std::unordered_map<long long, double> System::Impl::compliantOverlaps() const
{
    std::unordered_map<long long, double> out;
    const int N = int(x.size());
    const double dt = lastDt;
    if (!(dt > 0) || !anyCompliance()) return out;
    // the law of the step the impulses were solved in: relativeCompliance's
    // T (the step asked for) over its sub-step dt
    const double lawDt = lastComplianceDt > 0 ? lastComplianceDt : dt;
    const double ratio2 = (lawDt / dt) * (lawDt / dt);
    auto inverseMass = [&](int g) { return fix[g] ? 0.0 : 1.0 / mass[g]; };
    auto complianceOf = [&](int g)
    {
        const Material& m = materials[mat[g]];
        return std::array<double, 2>{m.compliance, m.relativeCompliance};
    };
    for (const Contact& c : contacts)
    {
        const int cj = keptBody(c);
        if (!(c.rn > 0) || cj >= N + int(walls.size())) continue; // unloaded, or a droplet
        const int gi = order[c.i];
        const int gj = cj < N ? order[cj] : -(cj - N + 1);
        const std::array<double, 2> a = complianceOf(gi);
        const std::array<double, 2> b = gj >= 0 ? complianceOf(gj) : a;
        // the step's own W_nn (effective masses); a seeded contact has none
        const double wnn = c.wnn > 0 ? c.wnn : inverseMass(gi) + (gj >= 0 ? inverseMass(gj) : 0.0);
        const double eps = law::CompliantSignorini::contactRegularisation(a, gj >= 0 ? &b : nullptr, wnn,
                                                                          1.0 / (dt * dt), ratio2);
        if (eps > 0)
        {
            // a grain may touch one wall (a mesh patch) at several faces:
            // the check takes its largest overlap, so admit the largest
            double& admitted = out[gj >= 0 ? pairKey(std::min(gi, gj), std::max(gi, gj)) : pairKey(gi, gj)];
            admitted = std::max(admitted, eps * dt * c.rn);
        }
    }
    return out;
}

void System::checkInitialOverlaps() const
{
    const Impl& I = *impl_;
    const int N = int(I.x.size());
    if (N == 0) return;
    const double tol = I.settings.overlapTolerance * I.rMin();
    // a loaded compliant contact's overlap is its law's own: admitted on
    // top of the tolerance
    const std::unordered_map<long long, double> lawOverlap = I.compliantOverlaps();
    auto admitted = [&](int i, int j)
    {
        if (lawOverlap.empty()) return tol;
        const auto it = lawOverlap.find(pairKey(i, j));
        return it == lawOverlap.end() ? tol : tol + it->second;
    };
    std::vector<std::string> msgs;
    int count = 0;
    double worst = 0;
    auto report = [&](const std::string& what, double ov)
    {
        ++count;
        worst = std::max(worst, ov);
        if (msgs.size() < 20)
        {
            std::ostringstream os;
            os << "  " << what << ": overlap " << ov << " m";
            msgs.push_back(os.str());
        }
    };
    // grain-grain: hash grid with cell = 2 r_max
    const double h = 2 * I.rMax();
    std::unordered_map<long long, std::vector<int>> grid;
    auto key = [&](long a, long b, long c) { return (a * 73856093LL) ^ (b * 19349663LL) ^ (c * 83492791LL); };
    auto cellOf = [&](const Vec3& p, long c[3])
    {
        for (int d = 0; d < 3; ++d) c[d] = long(std::floor(p[d] / h));
    };
    for (int i = 0; i < N; ++i)
    {
        long c[3];
        cellOf(I.x[i], c);
        grid[key(c[0], c[1], c[2])].push_back(i);
    }
    for (int i = 0; i < N; ++i)
    {
        long c[3];
        cellOf(I.x[i], c);
        for (long a = c[0] - 1; a <= c[0] + 1; ++a)
            for (long b = c[1] - 1; b <= c[1] + 1; ++b)
                for (long z = c[2] - 1; z <= c[2] + 1; ++z)
                {
                    auto it = grid.find(key(a, b, z));
                    if (it == grid.end()) continue;
                    for (int j : it->second)
                    {
                        if (j <= i) continue;
                        if (I.fix[i] && I.fix[j]) continue; // neither can move: never a contact
                        long cj[3];
                        cellOf(I.x[j], cj);
                        if (cj[0] != a || cj[1] != b || cj[2] != z) continue; // hash collision
                        const double ov = I.rad[i] + I.rad[j] - (I.x[i] - I.x[j]).norm();
                        if (ov > admitted(i, j))
                        {
                            std::ostringstream os;
                            os << "grains " << i << " and " << j;
                            report(os.str(), ov);
                        }
                    }
                }
    }
    // grain-wall
    std::vector<int> cand;
    for (int wi = 0; wi < int(I.walls.size()); ++wi)
    {
        const Wall& W = I.walls[wi];
        for (int i = 0; i < N; ++i)
        {
            if (I.fix[i]) continue; // fixed grains never contact walls
            double ov = 0;
            if (W.type == PlaneWall)
                ov = I.rad[i] - (I.x[i] - (W.p + W.displacement)).dot(W.n);
            else if (W.type == SegmentWall)
            {
                const Vec3 a = W.p + W.displacement, b = W.b + W.displacement;
                const Vec3 ab = b - a;
                const double t = std::clamp((I.x[i] - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
                ov = I.rad[i] - (I.x[i] - (a + t * ab)).norm();
            }
            else
            {
                const Vec3 xl = I.x[i] - W.displacement;
                trianglesNear(*W.tree, xl, I.rad[i], cand);
                for (int t : cand)
                {
                    const auto& f = W.triangles[t];
                    const Vec3 cp =
                        closestPointTriangle(xl, W.vertices[f[0]], W.vertices[f[1]], W.vertices[f[2]]);
                    ov = std::max(ov, I.rad[i] - (xl - cp).norm());
                }
            }
            if (ov > admitted(i, -(wi + 1)))
            {
                std::ostringstream os;
                os << "grain " << i << " and wall " << wi;
                report(os.str(), ov);
            }
        }
    }
    if (count > 0)
    {
        std::ostringstream os;
        os << "nscd::System::checkInitialOverlaps: " << count << " overlap(s) above the tolerance " << tol
           << " m (overlapTolerance " << I.settings.overlapTolerance << " x r_min), worst " << worst
           << " m:\n";
        for (const auto& m : msgs) os << m << "\n";
        if (count > int(msgs.size())) os << "  ... and " << count - int(msgs.size()) << " more\n";
        if (I.anyCompliance() && I.impulseScaledMaterial >= 0)
            os << "  The density of material " << I.impulseScaledMaterial << " was changed after the contact"
               << " impulses were set (setMaterial): they were scaled by " << I.materialImpulseScale
               << ", the weight the grains now carry, and a compliant contact admits the overlap c F_n of its"
               << " law at that load. A bed settled at the former density keeps its overlaps with the"
               << " absolute compliance divided by " << I.materialImpulseScale
               << " (relativeCompliance does so by itself).\n";
        throw InputError(os.str());
    }
}

std::size_t System::nContacts() const { return impl_->contacts.size(); }

double System::lastStepDt() const { return impl_->lastDt; }

void System::setComplianceStep(double T)
{
    if (!(T >= 0) || !std::isfinite(T))
        throw InputError(
            "nscd::System::setComplianceStep: the step must be >= 0 and finite (0: each step's own dt),"
            " got "
            + std::to_string(T));
    impl_->complianceDt = T;
}

double System::complianceStep() const { return impl_->complianceDt; }

void System::setContactImpulses(const std::vector<ContactView>& views, double dt)
{
    Impl& I = *impl_;
    if (!(dt > 0) || !std::isfinite(dt)) throw InputError("nscd::System::setContactImpulses: dt must be > 0");
    const int N = int(I.x.size());
    const int NW = int(I.walls.size());
    std::vector<Contact> cs;
    cs.reserve(views.size());
    for (std::size_t k = 0; k < views.size(); ++k)
    {
        const ContactView& v = views[k];
        int i = v.i, j = v.j;
        Vec3 n = v.normal, P = v.impulse;
        const bool bad =
            i < 0 || i >= N || j >= N || (j < 0 && -j - 1 >= NW) || i == j || !(n.norm() > 0) || v.age < 0;
        if (bad) throw InputError("nscd::System::setContactImpulses: bad contact " + std::to_string(k));
        // grains to slots (the records index grains by slot), pairs with i < j
        i = I.slotOf[i];
        if (j >= 0) j = I.slotOf[j];
        if (j >= 0 && j < i)
        {
            std::swap(i, j);
            n = -n;
            P = -P;
        }
        n.normalize();
        if (I.dim == 2)
        {
            n.z() = 0;
            P.z() = 0;
            n.normalize();
        }
        Contact c;
        c.i = i;
        c.j = j >= 0 ? j : N + (-j - 1);
        c.n = n;
        c.rn = P.dot(n);
        c.rt = P - c.rn * n;
        c.age = v.age;
        cs.push_back(c);
    }
    std::stable_sort(cs.begin(), cs.end(), [](const Contact& a, const Contact& b) { return a.i < b.i; });
    I.contacts = std::move(cs);
    I.keptContactsN = -1; // written for the grains there are now
    I.lastDt = dt;
    I.lastComplianceDt = 0; // impulses of a step dt
}

std::vector<System::ContactView> System::contacts() const
{
    const Impl& I = *impl_;
    std::vector<ContactView> out;
    out.reserve(I.contacts.size());
    for (Contact c : I.contacts)
    {
        c.j = I.keptBody(c); // (grains added since the last step)
        out.push_back(I.contactView(c));
    }
    return out;
}

System::ContactView System::Impl::contactView(const Contact& c) const
{
    const int N = int(x.size());
    ContactView v;
    v.i = order[c.i]; // slots to grains
    v.j = c.j < N ? order[c.j] : -(c.j - N + 1);
    v.normal = c.n;
    v.impulse = c.rn * c.n + c.rt;
    if (v.j >= 0 && v.j < v.i) // grain pairs with i < j, whatever the internal order
    {
        std::swap(v.i, v.j);
        v.normal = -v.normal;
        v.impulse = -v.impulse;
    }
    // contact point on A's surface (current position, normal of the last step)
    v.point = x[v.i] - rad[v.i] * v.normal;
    v.gap = c.gap;
    v.age = c.age;
    v.cohesive = c.coh > 0;
    return v;
}

// Units: eq. 4.2 is dimensionally inconsistent (the 1/4 power gives
// W m^-1/2 K^-1); it is evaluated literally in SI with L = 1 m and the value
// is taken as [W/K] in 3D and [W/(m K)] per unit depth in 2D (the thesis'
// cylinder formula is used for spheres as well).
double System::contactConductance(const ContactView& c, double dt) const
{
    const Impl& I = *impl_;
    if (c.i < 0 || c.i >= int(I.x.size()) || c.j >= int(I.x.size())
        || (c.j < 0 && -c.j - 1 >= int(I.walls.size())))
        throw InputError("nscd::System::contactConductance: unknown grain or wall in the contact");
    return I.conductance(c.i, c.j, c.impulse.dot(c.normal), dt);
}

} // namespace nscd
