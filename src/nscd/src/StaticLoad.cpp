// SPDX-License-Identifier: GPL-3.0-or-later
// The contact network of grains at rest: System::touchingContacts (detection
// without a step) and staticLoad (forces inside the Coulomb cones, top down;
// StaticLoad.H).
#include "nscd/StaticLoad.H"
#include "SystemImpl.H"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <string>

namespace nscd
{

std::vector<System::ContactView> System::touchingContacts(double touchDistance)
{
    if (!(touchDistance >= 0) || !std::isfinite(touchDistance))
        throw InputError("nscd::System::touchingContacts: touchDistance must be >= 0 and finite, got "
                         + std::to_string(touchDistance));
    Impl& I = *impl_;
    const int N = int(I.x.size());
    std::vector<ContactView> out;
    if (N == 0) return out;
    // The step's detection at the current velocities over dt = 0: the reach
    // of every body is then alertMargin r_min, raised to cover touchDistance.
    // Only solver scratch (bodies, detection records, newContacts) changes;
    // the next step rebuilds it. The grid scan itself (verletSkin 0): the
    // Verlet list of the steps is neither used (its reach may be smaller)
    // nor changed.
    const double margin = I.settings.alertMargin, skin = I.settings.verletSkin;
    I.settings.alertMargin = std::max(margin, 2 * touchDistance / I.rMin());
    I.settings.verletSkin = 0;
    I.freeVelocities(0);
    I.detect(0);
    I.settings.alertMargin = margin;
    I.settings.verletSkin = skin;
    // freshly detected records: impulse 0, age 0, not cohesive
    for (const Contact& c : I.newContacts)
        if (c.gap <= touchDistance) out.push_back(I.contactView(c));
    I.newContacts.clear();
    return out;
}

namespace
{
/**
 * Non-negative least squares min |A x - b|, x >= 0 (Lawson & Hanson 1974,
 * algorithm NNLS of ch. 23), for the few columns of one grain's supports.
 * A must have full column rank (here: regularised rows below the normals).
 */
Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b)
{
    const int n = int(A.cols());
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    std::vector<bool> passive(n, false);
    const double tol = 1e-12 * std::max(1.0, b.norm()) * std::max(1.0, A.norm());
    for (int outer = 0; outer < 3 * n + 3; ++outer)
    {
        const Eigen::VectorXd w = A.transpose() * (b - A * x);
        int t = -1;
        double wmax = tol;
        for (int j = 0; j < n; ++j)
            if (!passive[j] && w(j) > wmax)
            {
                wmax = w(j);
                t = j;
            }
        if (t < 0) break;
        passive[t] = true;
        for (int inner = 0; inner < 3 * n + 3; ++inner)
        {
            std::vector<int> P;
            for (int j = 0; j < n; ++j)
                if (passive[j]) P.push_back(j);
            Eigen::MatrixXd AP(A.rows(), P.size());
            for (std::size_t k = 0; k < P.size(); ++k) AP.col(k) = A.col(P[k]);
            const Eigen::VectorXd sP = AP.colPivHouseholderQr().solve(b);
            Eigen::VectorXd s = Eigen::VectorXd::Zero(n);
            for (std::size_t k = 0; k < P.size(); ++k) s(P[k]) = sP(k);
            double alpha = 1;
            bool feasible = true;
            for (int j : P)
                if (s(j) <= 0)
                {
                    feasible = false;
                    const double a = x(j) / (x(j) - s(j));
                    alpha = std::min(alpha, a);
                }
            if (feasible)
            {
                x = s;
                break;
            }
            x += alpha * (s - x);
            for (int j : P)
                if (x(j) <= 1e-15 * std::max(1.0, x.cwiseAbs().maxCoeff()))
                {
                    x(j) = 0;
                    passive[j] = false;
                }
        }
    }
    return x;
}

/// The input checks of staticLoad (InputError).
void checkInput(const System& sys, const std::vector<System::ContactView>& touching, double dt, double mu)
{
    if (!(dt > 0) || !std::isfinite(dt))
        throw InputError("nscd::staticLoad: dt must be > 0 and finite, got " + std::to_string(dt));
    if (!(mu >= 0) || !std::isfinite(mu))
        throw InputError("nscd::staticLoad: friction mu must be >= 0 and finite, got " + std::to_string(mu));
    if (!(sys.gravity().norm() > 0))
        throw InputError("nscd::staticLoad: gravity is zero: no weight to carry");
    const int N = int(sys.size());
    const int NW = sys.nWalls();
    for (const System::ContactView& c : touching)
        if (c.i < 0 || c.i >= N || c.j >= N || (c.j < 0 && -c.j - 1 >= NW) || c.i == c.j)
            throw InputError("nscd::staticLoad: contact (" + std::to_string(c.i) + ", " + std::to_string(c.j)
                             + ") names an unknown grain or wall");
}

/// The movable grains in visit order (order, or from the top down along
/// -g), and each grain's rank in it (fixed grains: N + 1, never visited).
std::vector<int> visitOrder(const System& sys, const std::vector<int>& order, std::vector<long>& rank)
{
    const int N = int(sys.size());
    const Vec3 g = sys.gravity();
    const Vec3 up = -g / g.norm();
    const std::vector<Vec3>& x = sys.positions();
    std::vector<int> byHeight;
    for (int i = 0; i < N; ++i)
        if (!sys.fixed(i)) byHeight.push_back(i);
    rank.assign(N, long(N) + 1);
    if (order.empty())
    {
        std::sort(byHeight.begin(), byHeight.end(),
                  [&](int a, int b) { return x[a].dot(up) > x[b].dot(up); });
    }
    else
    {
        bool ok = order.size() == byHeight.size();
        for (int i : order)
        {
            ok = ok && i >= 0 && i < N && !sys.fixed(i) && rank[i] > N;
            if (ok) rank[i] = 0;
        }
        if (!ok)
            throw InputError("nscd::staticLoad: order must list every movable grain once ("
                             + std::to_string(byHeight.size()) + " grains), got "
                             + std::to_string(order.size()) + " entries");
        byHeight = order;
    }
    for (std::size_t r = 0; r < byHeight.size(); ++r) rank[byHeight[r]] = long(r);
    return byHeight;
}
} // namespace

StaticLoad staticLoad(const System& sys, const std::vector<System::ContactView>& touching, double dt,
                      const std::vector<int>& order, double mu)
{
    checkInput(sys, touching, dt, mu);
    const Vec3 g = sys.gravity();
    const double gn = g.norm();
    const int N = int(sys.size());

    // the contacts of each grain
    std::vector<std::vector<int>> of(N);
    for (int k = 0; k < int(touching.size()); ++k)
    {
        of[touching[k].i].push_back(k);
        if (touching[k].j >= 0) of[touching[k].j].push_back(k);
    }
    // movable grains from the top down (visit rank; fixed grains: never)
    std::vector<long> rank;
    const std::vector<int> byHeight = visitOrder(sys, order, rank);

    StaticLoad out;
    out.contacts = touching;
    const int dim = sys.dimension();
    // 2D with friction: each support's force in the cone spanned by its two
    // edges u +- mu t (t = z x u), and the torque balanced as well
    const bool frictional = dim == 2 && mu > 0;
    const std::vector<double>& rad = sys.radii();
    std::vector<Vec3> force(touching.size(), Vec3::Zero()); // on grain A of each contact
    std::vector<Vec3> load(N, Vec3::Zero());
    std::vector<double> torque(N, 0.0); // 2D: about z [N m]
    auto cross2 = [](const Vec3& a, const Vec3& b) { return a.x() * b.y() - a.y() * b.x(); };
    for (int a : byHeight)
    {
        const Vec3 L = load[a] + sys.mass(a) * g;
        const double ra = rad[a];
        // supports: contacts with walls, fixed grains and grains visited later
        std::vector<int> sup;
        std::vector<Vec3> dirs; // unit normal from the support to a
        for (int k : of[a])
        {
            const System::ContactView& c = touching[k];
            const int other = c.i == a ? c.j : c.i;
            if (other >= 0 && rank[other] <= rank[a]) continue;
            sup.push_back(k);
            dirs.push_back(c.i == a ? c.normal : Vec3(-c.normal));
        }
        // columns: the cone edges of each support (force, then torque/r_a)
        const int edges = frictional ? 2 : 1;
        const int m = int(sup.size()) * edges;
        const int rows = dim + (dim == 2 ? 1 : 0);
        std::vector<Vec3> edgeForce(m);
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(rows + m, m);
        for (int k = 0; k < int(sup.size()); ++k)
            for (int e = 0; e < edges; ++e)
            {
                const Vec3& u = dirs[k];
                const Vec3 t(-u.y(), u.x(), 0);
                const double sgn = e == 0 ? 1 : -1;
                const Vec3 f = frictional ? Vec3(u + sgn * mu * t) : u;
                const int col = k * edges + e;
                edgeForce[col] = f;
                for (int d = 0; d < dim; ++d) A(d, col) = f(d);
                if (dim == 2) A(2, col) = cross2(-u, f); // torque / r_a
                A(rows + col, col) = 1e-4;
            }
        const double scale = std::max(L.norm(), std::abs(torque[a]) / ra);
        Eigen::VectorXd coef = Eigen::VectorXd::Zero(m);
        if (m > 0 && scale > 0)
        {
            Eigen::VectorXd b = Eigen::VectorXd::Zero(rows + m);
            for (int d = 0; d < dim; ++d) b(d) = -L(d) / scale;
            if (dim == 2) b(2) = -torque[a] / (ra * scale);
            coef = scale * nnls(A, b);
        }
        Vec3 residF = L;
        double residT = torque[a];
        for (int k = 0; k < int(sup.size()); ++k)
        {
            Vec3 F = Vec3::Zero();
            for (int e = 0; e < edges; ++e) F += coef(k * edges + e) * edgeForce[k * edges + e];
            const System::ContactView& c = touching[sup[k]];
            const Vec3& u = dirs[k];
            residF += F;
            residT += ra * cross2(-u, F);
            force[sup[k]] = c.i == a ? F : Vec3(-F);
            const int other = c.i == a ? c.j : c.i;
            if (other >= 0 && !sys.fixed(other))
            {
                load[other] -= F;
                torque[other] += rad[other] * cross2(u, -F);
            }
        }
        const double imb = std::sqrt(residF.squaredNorm() + (dim == 2 ? residT * residT / (ra * ra) : 0.0))
                           / (sys.mass(a) * gn);
        out.maxImbalance = std::max(out.maxImbalance, imb);
        if (imb > 1e-6) ++out.unbalanced;
    }
    for (std::size_t k = 0; k < touching.size(); ++k) out.contacts[k].impulse = force[k] * dt;
    return out;
}

} // namespace nscd
