// Sub-stepping, checks, contact views, conductance.
#include "SystemImpl.H"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace nscd
{

namespace
{
    /// Fastest body of a step dt: max over grains of |v_free| + r |w + alpha dt|
    /// (free velocity), walls and droplets; who: grain id >= 0, -1 wall, -2 droplet.
    struct Fastest { double v = 0; int who = -1; };

    template <class ImplT>
    Fastest fastest(const ImplT& I, double dt)
    {
        Fastest f;
        f.who = -3;  // nothing moves
        const int N = int(I.x.size());
        for (int i = 0; i < N; ++i)
        {
            Vec3 v = I.v[i], w = I.w[i];
            if (!I.fix[i])
            {
                v = I.freeVelocity(i, dt);
                if (!I.rotLock[i]) w += dt*I.torque[i]/I.inertia[i];
            }
            if (I.dim == 2) { v.z() = 0; w.x() = w.y() = 0; }
            const double s = v.norm() + I.rad[i]*w.norm();
            // std::isfinite first: comparing a NaN raises FE_INVALID (SIGFPE when trapped)
            if (!std::isfinite(s)) { f.v = s; f.who = i; return f; }
            if (s > f.v) { f.v = s; f.who = i; }
        }
        for (const auto& W : I.walls)
            if (W.velocity.norm() > f.v) { f.v = W.velocity.norm(); f.who = -1; }
        for (const auto& D : I.droplets)
        {
            Vec3 v = D.velocity;
            if (D.mass > 0) v += dt*D.force/D.mass;
            if (v.norm() > f.v) { f.v = v.norm(); f.who = -2; }
        }
        return f;
    }

    template <class ImplT>
    double subStepOf(const ImplT& I, double dt, double fraction, double vmax)
    {
        const double dmin = 2*I.rMin();
        if (vmax*dt <= fraction*dmin || dmin == 0) return dt;
        const double n = std::ceil(vmax*dt/(fraction*dmin)*(1 - 1e-12));  // guard round-off
        return dt/n;
    }
}

double System::subStep(double dt, double fraction) const
{
    const Impl& I = *impl_;
    if (!(dt > 0)) throw InputError("nscd::System::subStep: dt must be > 0");
    if (!(fraction > 0)) throw InputError("nscd::System::subStep: fraction must be > 0");
    return subStepOf(I, dt, fraction, fastest(I, dt).v);
}

StepReport System::advance(double dt, double fraction)
{
    if (!(dt > 0)) throw InputError("nscd::System::advance: dt must be > 0");
    if (!(fraction > 0)) throw InputError("nscd::System::advance: fraction must be > 0");
    const Impl& I = *impl_;
    const long maxSub = I.settings.maxSubSteps;
    if (maxSub < 1) throw InputError("nscd::System::advance: maxSubSteps must be >= 1");
    StepReport total;
    double remaining = dt;
    using clock = std::chrono::steady_clock;
    clock::time_point lastBeat = clock::now();
    const auto beatEvery = std::chrono::duration<double>(I.settings.heartbeatSeconds);
    while (remaining > 0)
    {
        const Fastest f = fastest(I, remaining);
        if (!std::isfinite(f.v))
        {
            std::ostringstream os;
            os << "nscd::System::advance: grain " << f.who << " has a non-finite velocity, force or"
               << " torque at the start of a sub-step (force " << I.force[f.who].transpose()
               << " N, velocity " << I.v[f.who].transpose() << " m/s)";
            throw StepError(os.str());
        }
        double h = subStepOf(I, remaining, fraction, f.v);
        if (h >= remaining*(1 - 1e-12)) h = remaining;
        const double needed = total.substeps + std::ceil(remaining/h*(1 - 1e-12));
        if (needed > double(maxSub))
        {
            std::ostringstream os;
            os << "nscd::System::advance: the step of " << dt << " s needs about " << needed
               << " sub-steps, more than maxSubSteps = " << maxSub << " (";
            if (f.who >= 0)
            {
                os << "grain " << f.who << " moves at " << f.v << " m/s with the step's forces, external force "
                   << I.force[f.who].norm() << " N";
                if (I.g.norm() > 0) os << " (" << I.force[f.who].norm()/(I.mass[f.who]*I.g.norm()) << " x its weight)";
            }
            else
                os << (f.who == -1 ? "a wall" : "a droplet") << " moves at " << f.v << " m/s";
            os << "; a sub-step may move a grain by " << fraction << " d_min = " << fraction*2*I.rMin() << " m)";
            throw StepError(os.str());
        }
        const StepReport r = step(h);
        remaining = (h == remaining) ? 0.0 : remaining - h;
        if (I.settings.heartbeat && remaining > 0 && clock::now() - lastBeat >= beatEvery)
        {
            I.settings.heartbeat(total.substeps + 1, total.substeps + 1 + remaining/h);
            lastBeat = clock::now();
        }
        total.contacts = std::max(total.contacts, r.contacts);
        total.sweeps += r.sweeps;
        total.localSolves += r.localSolves;
        total.residual = std::max(total.residual, r.residual);
        total.converged = total.converged && r.converged;
        total.substeps += 1;
        total.maxOverlap = std::max(total.maxOverlap, r.maxOverlap);
        total.detectSeconds += r.detectSeconds;
        total.solveSeconds += r.solveSeconds;
        total.wallHeat += r.wallHeat;
        total.fixedGrainHeat += r.fixedGrainHeat;
        total.sourceHeat += r.sourceHeat;
        total.exchangeHeat += r.exchangeHeat;
        total.heatIterations += r.heatIterations;
        total.heatResidual = std::max(total.heatResidual, r.heatResidual);
        total.heatSeconds += r.heatSeconds;
        total.cohesiveContacts = r.cohesiveContacts;  // the last sub-step's
    }
    return total;
}

void System::checkInitialOverlaps() const
{
    const Impl& I = *impl_;
    const int N = int(I.x.size());
    if (N == 0) return;
    const double tol = I.settings.overlapTolerance*I.rMin();
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
    const double h = 2*I.rMax();
    std::unordered_map<long long, std::vector<int>> grid;
    auto key = [&](long a, long b, long c) { return (a*73856093LL) ^ (b*19349663LL) ^ (c*83492791LL); };
    auto cellOf = [&](const Vec3& p, long c[3]) { for (int d = 0; d < 3; ++d) c[d] = long(std::floor(p[d]/h)); };
    for (int i = 0; i < N; ++i) { long c[3]; cellOf(I.x[i], c); grid[key(c[0], c[1], c[2])].push_back(i); }
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
                if (I.fix[i] && I.fix[j]) continue;  // neither can move: never a contact
                long cj[3];
                cellOf(I.x[j], cj);
                if (cj[0] != a || cj[1] != b || cj[2] != z) continue;  // hash collision
                const double ov = I.rad[i] + I.rad[j] - (I.x[i] - I.x[j]).norm();
                if (ov > tol)
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
            if (I.fix[i]) continue;  // fixed grains never contact walls
            double ov = 0;
            if (W.type == PlaneWall) ov = I.rad[i] - (I.x[i] - (W.p + W.displacement)).dot(W.n);
            else if (W.type == SegmentWall)
            {
                const Vec3 a = W.p + W.displacement, b = W.b + W.displacement;
                const Vec3 ab = b - a;
                const double t = std::clamp((I.x[i] - a).dot(ab)/ab.squaredNorm(), 0.0, 1.0);
                ov = I.rad[i] - (I.x[i] - (a + t*ab)).norm();
            }
            else
            {
                const Vec3 xl = I.x[i] - W.displacement;
                trianglesNear(*W.tree, xl, I.rad[i], cand);
                for (int t : cand)
                {
                    const auto& f = W.triangles[t];
                    const Vec3 cp = closestPointTriangle(xl, W.vertices[f[0]], W.vertices[f[1]], W.vertices[f[2]]);
                    ov = std::max(ov, I.rad[i] - (xl - cp).norm());
                }
            }
            if (ov > tol)
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
        os << "nscd::System::checkInitialOverlaps: " << count << " overlap(s) above the tolerance "
           << tol << " m (overlapTolerance " << I.settings.overlapTolerance << " x r_min), worst "
           << worst << " m:\n";
        for (const auto& m : msgs) os << m << "\n";
        if (count > int(msgs.size())) os << "  ... and " << count - int(msgs.size()) << " more\n";
        throw InputError(os.str());
    }
}

std::size_t System::nContacts() const { return impl_->contacts.size(); }

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
        const bool bad = i < 0 || i >= N || j >= N || (j < 0 && -j - 1 >= NW) || i == j || !(n.norm() > 0)
                         || v.age < 0;
        if (bad) throw InputError("nscd::System::setContactImpulses: bad contact " + std::to_string(k));
        if (j >= 0 && j < i) { std::swap(i, j); n = -n; P = -P; }
        n.normalize();
        if (I.dim == 2) { n.z() = 0; P.z() = 0; n.normalize(); }
        Contact c;
        c.i = i;
        c.j = j >= 0 ? j : N + (-j - 1);
        c.n = n;
        c.rn = P.dot(n);
        c.rt = P - c.rn*n;
        c.age = v.age;
        cs.push_back(c);
    }
    std::stable_sort(cs.begin(), cs.end(), [](const Contact& a, const Contact& b) { return a.i < b.i; });
    I.contacts = std::move(cs);
    I.lastDt = dt;
}

std::vector<System::ContactView> System::contacts() const
{
    const Impl& I = *impl_;
    const int N = int(I.x.size());
    std::vector<ContactView> out;
    out.reserve(I.contacts.size());
    for (const Contact& c : I.contacts)
    {
        ContactView v;
        v.i = c.i;
        v.j = c.j < N ? c.j : -(c.j - N + 1);
        v.normal = c.n;
        // contact point on A's surface (current position, normal of the last step)
        v.point = I.x[c.i] - I.rad[c.i]*c.n;
        v.gap = c.gap;
        v.impulse = c.rn*c.n + c.rt;
        v.age = c.age;
        v.cohesive = c.coh > 0;
        out.push_back(v);
    }
    return out;
}

double System::contactConductance(const ContactView& c, double dt) const
{
    const Impl& I = *impl_;
    if (c.i < 0 || c.i >= int(I.x.size()) || c.j >= int(I.x.size())
        || (c.j < 0 && -c.j - 1 >= int(I.walls.size())))
        throw InputError("nscd::System::contactConductance: unknown grain or wall in the contact");
    return I.conductance(c.i, c.j, c.impulse.dot(c.normal), dt);
}

} // namespace nscd
