// SPDX-License-Identifier: GPL-3.0-or-later
// Newton contact solve for compliant contacts (System::Settings::Method::Newton):
// the primal, unconstrained convex formulation of compliant contact of
// A. M. Castro, F. N. Permenter & X. Han, "An unconstrained convex
// formulation of compliant contact", IEEE Trans. Robotics 39(2), 2023
// (Drake's SAP; MuJoCo's Newton solver, E. Todorov, "Convex and analytically-
// invertible dynamics with contacts and constraints", ICRA 2014, is of the
// same family). Written from the paper; no code copied.
//
// Unknowns: the velocities v of the movable bodies (grains: translation,
// and rotation unless locked; 2D: v_x, v_y, w_z; 3D: v, w), size nv. Cost
//   l(v) = 1/2 (v - v*)^T M (v - v*) + sum_k [l_k(J_k v + c_k) + coh_k (J_k v + c_k)_n]
// M = diag(m + dt c_drag, I) (the NLGS's effective masses), v* the free
// velocities (eq. 2.11, the warm start's impulses removed), J_k the contact
// Jacobian in the contact's frame (n, t1[, t2]) and c_k the part of the
// contact velocity from bodies that are not unknowns (walls, fixed grains,
// locked rotations), l_k the cost of the regularised cone projection
// (NewtonCone.H) with R_n = eps (the compliant law's regularisation,
// ContactLaws.H), R_t = sigma R_n, vhat_n = -(bias - eps coh) (the law's
// gap term; cohesion shifts the cone to r_n >= -coh, r~ = r + coh e_n).
// grad l = M (v - v*) - sum_k J_k^T (gamma_k - coh_k e_n), so at the minimum
// M (v - v*) = J^T r with r = gamma - coh e_n: momentum balance with the
// compliant law's impulses (Castro et al., eq. 18-20 and Theorem 1).
// Each iteration is one linear solve with a matrix M + sum_k J_k^T B_k J_k
// (Eigen SparseMatrix, lower triangle, one pattern per step, filled in
// place; kept with its LDLT ordering for the next step when the rows touch
// the same unknowns), by SimplicialLDLT or incomplete-Cholesky CG
// (Settings::newtonLinearSolver). Two stages:
//  1. active-set steps (a primal-dual active-set method in the manner of
//     Hintermueller, Ito & Kunisch, SIAM J. Optim. 13(3), 2002, and of
//     Hueeber, Stadler & Wohlmuth, SIAM J. Sci. Comput. 30(2), 2008, for
//     Coulomb friction): each row keeps a region (stiction, sliding along
//     a direction, separation), first the warm start's (the previous
//     step's impulse), then updated from the model's solution: the step
//     goes to the minimiser of the quadratic model of l in which each row
//     keeps its region (B_k its curvature there), the full step;
//  2. when the regions settle without optimality, cycle or reach
//     maxActiveSetSteps: Newton's steps on l from the best iterate (B_k =
//     G_k at v, H dv = -grad l) with the exact line search on l along dv
//     (a safeguarded Newton-bisection on dl/dalpha; l is convex).
// Why not Newton on l alone, as the paper: a row's region at v is decided
// within mu R_t gamma_n of tangential velocity (R_t = sigma R_n, 6e-9 m/s
// a layer on the landing column with beta 2e-3, sigma 1e-3), far below
// the error of any iterate, so most loaded rows start in the wrong region;
// a wrong sliding row has no curvature along its slip (in 2D), Newton's
// step overshoots its stiction band by ~1/(mu^2 sigma), and the exact line
// search stops at the first such kink: a few rows corrected per iteration,
// an iteration count that grows with the rows (docs/validation/
// contactCompliance.md, "The Newton solver"). The regions carried by the
// active-set steps do not depend on the iterate's tangential noise.
// Stop on SAP's relative optimality test (Settings::newtonTolerance).
// At the end the bodies get v* + M^-1 J^T r(v) (momentum exactly
// consistent with the rows' impulses, as in the Gauss-Seidel methods) and
// the rows r(v); StepReport::residual is the common residual of every
// method (ContactSolver.cpp; it also sees the tangential creep R_t r_t).
#include "NewtonCone.H"
#include "SystemImpl.H"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>

namespace nscd
{

namespace
{

using SpMat = Eigen::SparseMatrix<double>;

/// Most Newton iterations, whatever Settings::maxIterations (SAP's default cap is 100).
constexpr int maxNewtonIterations = 200;
/// Most active-set steps of a solve before Newton's steps with the line search take over.
constexpr int maxActiveSetSteps = 40;
/// Relative residual of the conjugate-gradient linear solve (inexact Newton).
constexpr double cgTolerance = 1e-3;
/// Cost stall: a step that lowers l by less than this relative amount ends
/// the solve (the round-off floor of l; converged only if the test holds).
constexpr double costStall = 1e-14;

/**
 * The matrix pattern of the last solve on this thread, kept for the next:
 * the contacts of a bed at rest change little from step to step, and when
 * every row touches the same unknowns as before, the pattern of H, the
 * positions of the rows' entries and the LDLT's ordering and symbolic
 * analysis are reused. key lists nv and each row's unknowns.
 */
struct PatternCache
{
    std::vector<int> key;
    SpMat H;
    std::vector<int> diagSlot, slotStart, slots;
    Eigen::SimplicialLDLT<SpMat, Eigen::Lower> ldlt;
    bool analysed = false;  ///< ldlt's analyzePattern done for H's pattern
};
thread_local PatternCache patternCache;

/// One contact of the Newton solve: its Jacobian (local rows x the
/// unknowns it touches), the velocity of the bodies that are not unknowns,
/// and its law's constants.
struct NewtonRow
{
    int ncol = 0;        ///< unknowns touched (<= 12)
    int col[12];         ///< their indices in v
    double J[3][12];     ///< J_k (rows n, t1, t2) [m/s per unit of v]
    Eigen::Vector3d c0;  ///< contact velocity of the fixed parts [m/s]
    Eigen::Vector3d e[3];  ///< basis n, t1, t2 (global)
    double Rn = 0, Rt = 0, vhatN = 0, mu = 0, coh = 0;
    bool skip = false;   ///< no unknown touched: left out of the solve (impulse 0)
};

/// Everything the solve of one step needs.
struct NewtonSolve
{
    System::Impl& I;
    const double dt;
    const int m;      ///< local components: 2 (2D) or 3
    const int NC;
    std::vector<int> tDof, rDof;  ///< per body: first translational / rotational unknown (-1: none)
    int nv = 0;
    Eigen::VectorXd mass, vStar, v, grad, dv;
    std::vector<NewtonRow> R;
    std::vector<Eigen::Vector3d> vc, wc;  ///< contact velocities at v, J_k dv
    double cost = 0;
    double pNorm = 0, jNorm = 0, gNorm = 0;  ///< |D p|, |D j_c|, |D grad l|
    SpMat& H;                             ///< the Newton or region-model matrix (lower triangle)
    std::vector<int>& diagSlot;           ///< position of M's entries in H's values
    std::vector<int>& slotStart;          ///< per row: start of its entries' positions in slots
    std::vector<int>& slots;              ///< positions of the rows' block entries in H's values (-1: upper)

    NewtonSolve(System::Impl& impl, double dtStep)
    : I(impl), dt(dtStep), m(impl.dim == 2 ? 2 : 3), NC(int(impl.rows.size())), H(patternCache.H),
      diagSlot(patternCache.diagSlot), slotStart(patternCache.slotStart), slots(patternCache.slots) {}

    int nt() const { return I.dim == 2 ? 2 : 3; }  ///< translational unknowns per body
    int nr() const { return I.dim == 2 ? 1 : 3; }  ///< rotational unknowns per body

    /// Unknowns of the movable bodies and their masses; x0 the bodies' velocities.
    void numberUnknowns(Eigen::VectorXd& x0)
    {
        const int NB = int(I.body.size());
        tDof.assign(NB, -1);
        rDof.assign(NB, -1);
        nv = 0;
        for (int b = 0; b < NB; ++b)
        {
            if (!(I.body[b].im > 0)) continue;
            tDof[b] = nv; nv += nt();
            if (I.body[b].ii > 0) { rDof[b] = nv; nv += nr(); }
        }
        mass.resize(nv);
        x0.resize(nv);
        for (int b = 0; b < NB; ++b)
        {
            const Body& B = I.body[b];
            if (tDof[b] >= 0)
                for (int a = 0; a < nt(); ++a) { mass(tDof[b] + a) = 1.0/B.im; x0(tDof[b] + a) = B.v(a); }
            if (rDof[b] >= 0)
            {
                if (I.dim == 2) { mass(rDof[b]) = 1.0/B.ii; x0(rDof[b]) = B.w.z(); }
                else for (int a = 0; a < 3; ++a) { mass(rDof[b] + a) = 1.0/B.ii; x0(rDof[b] + a) = B.w(a); }
            }
        }
    }

    /// Jacobian rows of one body side (sign +1 for A, -1 for B) of row r.
    void addSide(NewtonRow& r, int b, double sign, const Vec3& n)
    {
        const Body& B = I.body[b];
        // contact velocity du = v_A - v_B - (r_A w_A + r_B w_B) x n
        // (eq. 2.14-2.18): along e, sign v . e - r w . (n x e), the
        // rotation's sign the same for A and B (their contact points are
        // at -r_A n and +r_B n)
        Vec3 nxe[3];
        for (int a = 0; a < m; ++a) nxe[a] = n.cross(r.e[a]);
        const Vec3 vFix = tDof[b] >= 0 ? Vec3::Zero() : B.v;
        const Vec3 wFix = rDof[b] >= 0 ? Vec3::Zero() : B.w;
        for (int a = 0; a < m; ++a) r.c0(a) += sign*vFix.dot(r.e[a]) - B.r*wFix.dot(nxe[a]);
        if (tDof[b] >= 0)
            for (int d = 0; d < nt(); ++d)
            {
                const int k = r.ncol++;
                r.col[k] = tDof[b] + d;
                for (int a = 0; a < m; ++a) r.J[a][k] = sign*r.e[a](d);
            }
        if (rDof[b] >= 0)
            for (int d = 0; d < nr(); ++d)
            {
                const int k = r.ncol++;
                const int comp = I.dim == 2 ? 2 : d;
                r.col[k] = rDof[b] + d;
                for (int a = 0; a < m; ++a) r.J[a][k] = -B.r*nxe[a](comp);
            }
    }

    /// The rows' Jacobians and law constants (throws InputError on a hard row).
    void buildRows(double sigma)
    {
        R.resize(NC);
        for (int k = 0; k < NC; ++k)
        {
            const SolverContact& s = I.rows[k];
            NewtonRow& r = R[k];
            const Vec3& n = s.n;
            r.e[0] = n;
            if (I.dim == 2) { r.e[1] = Vec3(-n.y(), n.x(), 0.0); r.e[2].setZero(); }
            else
            {
                // tangents: t1 orthogonal to n and to its smallest component's axis
                const Vec3 a = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
                r.e[1] = (a - a.dot(n)*n).normalized();
                r.e[2] = n.cross(r.e[1]);
            }
            r.ncol = 0;
            r.c0.setZero();
            addSide(r, s.i, 1.0, n);
            addSide(r, s.j, -1.0, n);
            // the compliant law's eps: iwnn = 1/(W_nn + eps) (prepareContacts)
            const double eps = s.iwnn > 0 ? 1.0/s.iwnn - s.wnn : 0.0;
            r.skip = r.ncol == 0;  // no movable body (e.g. a fixed grain on a wall): no impulse
            if (r.skip) continue;
            if (!(eps > 1e-12*s.wnn) || std::isfinite(s.cap))
                throw InputError("nscd::System::step: the Newton contact solver met a hard (zero-compliance) "
                                 "or capped contact (bodies " + std::to_string(s.i) + ", "
                                 + std::to_string(s.j) + "); every contact needs a compliance");
            r.Rn = eps;
            r.Rt = sigma*eps;
            r.mu = s.mu;
            r.coh = s.coh;
            r.vhatN = -(s.bias - eps*s.coh);
        }
    }

    /// Contact velocity J_k x + c0 of row k.
    Eigen::Vector3d contactVelocity(int k, const Eigen::VectorXd& x, bool withFixed) const
    {
        const NewtonRow& r = R[k];
        Eigen::Vector3d u = withFixed ? r.c0 : Eigen::Vector3d::Zero();
        for (int j = 0; j < r.ncol; ++j)
        {
            const double xj = x(r.col[j]);
            for (int a = 0; a < m; ++a) u(a) += r.J[a][j]*xj;
        }
        return u;
    }

    /// y += J_k^T f.
    void addJT(int k, const Eigen::Vector3d& f, Eigen::VectorXd& y) const
    {
        const NewtonRow& r = R[k];
        for (int j = 0; j < r.ncol; ++j)
        {
            double s = 0;
            for (int a = 0; a < m; ++a) s += r.J[a][j]*f(a);
            y(r.col[j]) += s;
        }
    }

    /// Impulse of row k on its bodies for the projection p: gamma - coh e_n.
    Eigen::Vector3d impulse(int k, const newton::ConeProjection& p) const
    {
        Eigen::Vector3d f = p.gamma;
        f(0) -= R[k].coh;
        return f;
    }

    /// Cost, gradient and the SAP norms at v (vc filled).
    void evaluate()
    {
        const Eigen::VectorXd dvStar = v - vStar;
        cost = 0.5*dvStar.dot(mass.cwiseProduct(dvStar));
        Eigen::VectorXd jc = Eigen::VectorXd::Zero(nv);
        vc.resize(NC);
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            vc[k] = contactVelocity(k, v, true);
            if (r.skip) continue;
            const newton::ConeProjection p = newton::project(vc[k], r.vhatN, r.Rn, r.Rt, r.mu, false);
            cost += p.cost + r.coh*vc[k](0);
            addJT(k, impulse(k, p), jc);
        }
        grad = mass.cwiseProduct(dvStar) - jc;
        const Eigen::VectorXd D = mass.cwiseSqrt().cwiseInverse();
        gNorm = grad.cwiseProduct(D).norm();
        pNorm = mass.cwiseProduct(v).cwiseProduct(D).norm();
        jNorm = jc.cwiseProduct(D).norm();
    }

    /// Regions of the rows' projections at v (ConeProjection::region; 2 for a skipped row); vc current.
    void regions(std::vector<int>& reg) const
    {
        reg.assign(NC, 2);
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            reg[k] = newton::project(vc[k], r.vhatN, r.Rn, r.Rt, r.mu, false).region;
        }
    }

    /// SAP's optimality ratio |D grad l| / max(|D p|, |D j_c|) at the last
    /// evaluate() (the residual history's entry).
    double optimality() const { return gNorm/std::max(std::max(pNorm, jNorm), 1e-300); }
    /// SAP's relative optimality test |D grad l| <= tol max(|D p|, |D j_c|).
    bool optimal(double tol) const { return gNorm <= tol*std::max(pNorm, jNorm); }

    /**
     * The pattern of H (lower triangle: M and every row's block J_k^T J_k,
     * whether its curvature is zero or not, so that one pattern serves the
     * whole solve), and where each row's block entries sit in H's values.
     */
    void buildPattern()
    {
        std::vector<int> key{nv};
        key.reserve(1 + 7*NC);
        for (const NewtonRow& r : R)
        {
            key.push_back(r.skip ? -1 : r.ncol);
            if (!r.skip) key.insert(key.end(), r.col, r.col + r.ncol);
        }
        if (key == patternCache.key) return;  // the last solve's pattern
        patternCache.key.swap(key);
        patternCache.analysed = false;
        std::vector<Eigen::Triplet<double>> T;
        for (int i = 0; i < nv; ++i) T.emplace_back(i, i, 0.0);
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            for (int i = 0; i < r.ncol; ++i)
                for (int j = 0; j < r.ncol; ++j)
                    if (r.col[i] >= r.col[j]) T.emplace_back(r.col[i], r.col[j], 0.0);
        }
        H.resize(nv, nv);
        H.setFromTriplets(T.begin(), T.end());
        H.makeCompressed();
        const double* v0 = H.valuePtr();
        diagSlot.resize(nv);
        for (int i = 0; i < nv; ++i) diagSlot[i] = int(&H.coeffRef(i, i) - v0);
        slotStart.assign(NC + 1, 0);
        slots.clear();
        for (int k = 0; k < NC; ++k)
        {
            slotStart[k] = int(slots.size());
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            for (int i = 0; i < r.ncol; ++i)
                for (int j = 0; j < r.ncol; ++j)
                    slots.push_back(r.col[i] >= r.col[j] ? int(&H.coeffRef(r.col[i], r.col[j]) - v0) : -1);
        }
        slotStart[NC] = int(slots.size());
    }

    /// H = M (the values of the fixed pattern reset).
    void resetHessian()
    {
        std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
        for (int i = 0; i < nv; ++i) H.valuePtr()[diagSlot[i]] = mass(i);
    }

    /// H += J_k^T B J_k (B symmetric 3x3 in the local frame; lower triangle).
    void addBlock(int k, const Eigen::Matrix3d& B)
    {
        const NewtonRow& r = R[k];
        double BJ[3][12];
        for (int a = 0; a < m; ++a)
            for (int j = 0; j < r.ncol; ++j)
            {
                double s = 0;
                for (int b = 0; b < m; ++b) s += B(a, b)*r.J[b][j];
                BJ[a][j] = s;
            }
        double* val = H.valuePtr();
        const int* slot = slots.data() + slotStart[k];
        for (int i = 0; i < r.ncol; ++i)
            for (int j = 0; j < r.ncol; ++j)
            {
                const int at = slot[i*r.ncol + j];
                if (at < 0) continue;
                double s = 0;
                for (int a = 0; a < m; ++a) s += r.J[a][i]*BJ[a][j];
                val[at] += s;
            }
    }

    /// Hessian of l at v, H = M + sum J^T G J (vc current).
    void hessian()
    {
        resetHessian();
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            addBlock(k, newton::project(vc[k], r.vhatN, r.Rn, r.Rt, r.mu, true).G);
        }
    }

    /// Gradient g and Hessian H at v of the quadratic model of l whose rows
    /// keep given regions: reg[k] 0 stiction (gamma = y extended beyond the
    /// cone), 1 sliding along the fixed direction slip[k] (unit, local
    /// tangential components), 2 separation (no impulse). vc must be current.
    void regionModel(const std::vector<int>& reg, const std::vector<Eigen::Vector3d>& slip, Eigen::VectorXd& g)
    {
        resetHessian();
        g = mass.cwiseProduct(v - vStar);
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            const double yn = -(vc[k](0) - r.vhatN)/r.Rn;
            Eigen::Vector3d f = Eigen::Vector3d::Zero();  // impulse gamma of the model
            Eigen::Matrix3d B = Eigen::Matrix3d::Zero();  // -d gamma/d v_c
            if (reg[k] == 0 || (reg[k] == 1 && r.mu == 0))
            {
                f(0) = yn;
                B(0, 0) = 1.0/r.Rn;
                if (r.mu > 0)
                    for (int a = 1; a < m; ++a) { f(a) = -vc[k](a)/r.Rt; B(a, a) = 1.0/r.Rt; }
            }
            else if (reg[k] == 1)
            {
                const double muHat = r.mu*r.Rt/r.Rn, c = 1.0/(1.0 + r.mu*muHat);
                double yts = 0;  // slip . y_t
                for (int a = 1; a < m; ++a) yts += -slip[k](a)*vc[k](a)/r.Rt;
                const double gn = c*(yn + muHat*yts);
                Eigen::Vector3d e = slip[k]*r.mu;  // d gn/d(-v_c) direction: (1, mu t)/R_n c
                e(0) = 1.0;
                f = gn*e;
                B = (c/r.Rn)*e*e.transpose();
            }  // separation: no impulse, no curvature (the block kept: one pattern)
            f(0) -= r.coh;
            addJT(k, -f, g);
            addBlock(k, B);
        }
    }

    /**
     * Regions of the region model at the start of a solve: a row that
     * carried a load in the warm start (the previous step's impulse) keeps
     * that impulse's region (stiction inside the cone, sliding on it, along
     * its direction); any other row takes the region of its projection at
     * v. vc must be current.
     */
    void initialRegions(std::vector<int>& reg, std::vector<Eigen::Vector3d>& slip) const
    {
        regions(reg);
        slip.assign(NC, Eigen::Vector3d::Zero());
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            Eigen::Vector3d f = warmImpulse(k);
            f(0) += r.coh;  // the cone's impulse gamma
            const double ft = std::hypot(f(1), f(2));
            if (f(0) > 0)
            {
                if (r.mu == 0 || ft < (1 - 1e-6)*r.mu*f(0)) { reg[k] = 0; continue; }
                reg[k] = 1;
                slip[k] = Eigen::Vector3d(0, f(1)/ft, f(2)/ft);
            }
            else if (reg[k] == 1)
                slip[k] = Eigen::Vector3d(0, -vc[k](1), -vc[k](2)).normalized();
        }
    }

    /// The warm start's impulse of row k (the rows' rn, rt) in its local frame.
    Eigen::Vector3d warmImpulse(int k) const
    {
        const SolverContact& c = I.rows[k];
        const Vec3 P = c.rn*c.n + c.rt;
        Eigen::Vector3d f = Eigen::Vector3d::Zero();
        for (int a = 0; a < m; ++a) f(a) = P.dot(R[k].e[a]);
        return f;
    }

    /// Sliding directions of the rows in region 1 from their projection at v (vc current).
    void initialSlip(const std::vector<int>& reg, std::vector<Eigen::Vector3d>& slip) const
    {
        slip.assign(NC, Eigen::Vector3d::Zero());
        for (int k = 0; k < NC; ++k)
            if (reg[k] == 1) slip[k] = Eigen::Vector3d(0, -vc[k](1), -vc[k](2)).normalized();
    }

    /**
     * The region model's update at v (vc current), the active-set rule of a
     * primal-dual active-set method: a sticking row whose impulse y has
     * left the cone slides, along y_t; a sliding row whose slip along its
     * direction has fallen into the stiction band (or reversed) sticks; a
     * row whose impulse vanishes (y_n <= -mu^ |y_t|) separates, and a
     * separated row that closes takes its projection's region.
     * @return the number of rows whose region changed.
     */
    int updateRegions(std::vector<int>& reg, std::vector<Eigen::Vector3d>& slip) const
    {
        int changes = 0;
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            const double yn = -(vc[k](0) - r.vhatN)/r.Rn;
            const Eigen::Vector3d yt(0, -vc[k](1)/r.Rt, -vc[k](2)/r.Rt);
            const double yr = yt.norm();
            const double muHat = r.mu*r.Rt/r.Rn;
            int now = reg[k];
            if (!(yn > -muHat*yr)) now = 2;
            else if (reg[k] == 1)
            {
                const double yts = slip[k].dot(yt);
                if (yts <= r.mu*yn) now = 0;
                else if (m == 3) slip[k] = yt/yr;
            }
            else if (r.mu > 0 && yr > r.mu*yn) { now = 1; slip[k] = yt/yr; }
            else now = 0;
            changes += now != reg[k];
            reg[k] = now;
        }
        return changes;
    }

    /// dl/dalpha and d2l/dalpha2 at v + alpha dv (wc = J dv, a = dv^T M dv,
    /// b = dv^T M (v - v*)).
    void lineDerivatives(double alpha, double a, double b, double& d1, double& d2) const
    {
        d1 = b + alpha*a;
        d2 = a;
        for (int k = 0; k < NC; ++k)
        {
            const NewtonRow& r = R[k];
            if (r.skip) continue;
            const Eigen::Vector3d u = vc[k] + alpha*wc[k];
            const newton::ConeProjection p = newton::project(u, r.vhatN, r.Rn, r.Rt, r.mu, true);
            d1 += -p.gamma.dot(wc[k]) + r.coh*wc[k](0);
            d2 += wc[k].dot(p.G*wc[k]);
        }
    }

    /// Exact line search: the root of dl/dalpha in (0, alphaMax] by Newton
    /// steps kept in the bracket (bisection otherwise); alphaMax if l still
    /// decreases there. @return alpha; evals counts the evaluations.
    double lineSearch(int& evals)
    {
        constexpr double alphaMax = 1.5;
        wc.resize(NC);
        for (int k = 0; k < NC; ++k) wc[k] = contactVelocity(k, dv, false);
        const double a = dv.dot(mass.cwiseProduct(dv));
        const double b = dv.dot(mass.cwiseProduct(v - vStar));
        double d1, d2;
        lineDerivatives(0.0, a, b, d1, d2);
        ++evals;
        const double d10 = d1;
        if (!(d10 < 0)) return 0.0;  // not a descent direction (round-off): stop
        double lo = 0, hi = alphaMax;
        lineDerivatives(hi, a, b, d1, d2);
        ++evals;
        if (d1 <= 0) return hi;
        double alpha = 1.0;
        for (int it = 0; it < 50; ++it)
        {
            lineDerivatives(alpha, a, b, d1, d2);
            ++evals;
            if (std::abs(d1) <= 1e-10*std::abs(d10)) break;
            if (d1 < 0) lo = alpha; else hi = alpha;
            if (hi - lo <= 1e-12*hi) break;
            const double next = d2 > 0 ? alpha - d1/d2 : -1.0;
            alpha = next > lo && next < hi ? next : 0.5*(lo + hi);
        }
        return alpha;
    }
};

} // namespace

void System::Impl::solveNewton(double dt, StepReport& rep)
{
    NewtonSolve S(*this, dt);
    const int NC = S.NC;
    const bool hist = settings.residualHistory;
    const double dmin = 2*rMin();
    rep.method = int(Settings::Method::Newton);
    rep.contacts = NC;
    Eigen::VectorXd x0;
    S.numberUnknowns(x0);
    S.buildRows(settings.tangentialRegularisation);
    // free velocities: the warm-started bodies minus the rows' impulses
    {
        Eigen::VectorXd jr = Eigen::VectorXd::Zero(S.nv);
        for (int k = 0; k < NC; ++k) S.addJT(k, S.warmImpulse(k), jr);
        S.vStar = x0 - jr.cwiseQuotient(S.mass);
    }
    S.v = x0;
    const double tol = settings.newtonTolerance;
    const int maxIt = std::min(settings.maxIterations, maxNewtonIterations);
    S.buildPattern();
    Eigen::SimplicialLDLT<SpMat, Eigen::Lower>& ldlt = patternCache.ldlt;
    Eigen::ConjugateGradient<SpMat, Eigen::Lower, Eigen::IncompleteCholesky<double, Eigen::Lower>> cg;
    const bool useCg = settings.newtonLinearSolver == Settings::NewtonLinearSolver::ConjugateGradient;
    bool& analysed = patternCache.analysed;
    long cgIterations = 0;
    // dv = -H^-1 g (the pattern of H is the same for every solve of the step)
    auto linearSolve = [&](const Eigen::VectorXd& g)
    {
        if (useCg)
        {
            cg.setTolerance(cgTolerance);
            cg.compute(S.H);
            S.dv = cg.solve(-g);
            cgIterations += cg.iterations();
        }
        else
        {
            if (!analysed) { ldlt.analyzePattern(S.H); analysed = true; }
            ldlt.factorize(S.H);
            S.dv = ldlt.solve(-g);
        }
    };
    int it = 0, evals = 0, activeSetSteps = 0;
    bool converged = false;
    S.evaluate();
    // Stage 1, active-set steps: the rows' regions are carried from step to
    // step (the warm start's) and from iteration to iteration (updateRegions),
    // not read off the iterate (see the head of this file). Each step goes to the
    // minimiser of the quadratic model with those regions (one linear solve),
    // the full step whatever the cost does there (the best iterate is kept).
    // Stage 2, when the regions settle without optimality, cycle or reach
    // maxActiveSetSteps: Newton's steps on l from the best iterate, with the
    // exact line search (convergent: l is convex and decreases at each step).
    std::vector<int> reg;
    std::vector<Eigen::Vector3d> slip;
    S.initialRegions(reg, slip);
    Eigen::VectorXd g;
    bool activeSet = true;
    Eigen::VectorXd bestV = S.v;
    double bestCost = S.cost;
    std::array<double, 8> recentCosts;  // the costs of the last active-set iterates (cycle detection)
    recentCosts.fill(-1.0);
    while (true)
    {
        if (hist) rep.residualHistory.push_back(S.optimality());
        if (S.nv == 0 || S.optimal(tol)) { converged = true; break; }
        if (it >= maxIt) break;
        ++it;
        if (activeSet)
        {
            S.regionModel(reg, slip, g);
            linearSolve(g);
            ++activeSetSteps;
            S.v += S.dv;
            S.evaluate();
            const int changes = S.updateRegions(reg, slip);
            if (S.cost < bestCost) { bestCost = S.cost; bestV = S.v; }
            bool cycle = false;  // the cost of one of the last iterates again: the regions cycle
            for (double c : recentCosts) cycle = cycle || std::abs(c - S.cost) <= 1e-12*std::abs(S.cost);
            recentCosts[activeSetSteps % recentCosts.size()] = S.cost;
            if ((changes == 0 && S.optimal(tol)) || !(changes == 0 || cycle || activeSetSteps >= maxActiveSetSteps))
                continue;
            activeSet = false;
            if (S.v != bestV) { S.v = bestV; S.evaluate(); }
            continue;
        }
        const double before = S.cost;
        S.hessian();
        linearSolve(S.grad);
        const double alpha = S.lineSearch(evals);
        if (!(alpha > 0)) break;  // no descent left (round-off): converged only by the test
        S.v += alpha*S.dv;
        S.evaluate();
        if (std::abs(before - S.cost) <= costStall*std::abs(S.cost))
        {
            // round-off floor of the cost: stop; converged only by the test
            if (hist) rep.residualHistory.push_back(S.optimality());
            converged = S.optimal(tol);
            break;
        }
    }
    // the rows' impulses r(v) and the bodies' velocities v* + M^-1 J^T r
    Eigen::VectorXd jr = Eigen::VectorXd::Zero(S.nv);
    const bool twoD = dim == 2;
    for (int k = 0; k < NC; ++k)
    {
        const NewtonRow& r = S.R[k];
        SolverContact& c = rows[k];
        if (r.skip) { c.rn = c.rts = 0; c.rt.setZero(); continue; }
        const newton::ConeProjection p = newton::project(S.contactVelocity(k, S.v, true), r.vhatN, r.Rn, r.Rt,
                                                         r.mu, false);
        const Eigen::Vector3d f = S.impulse(k, p);
        S.addJT(k, f, jr);
        c.rn = f(0);
        c.rt = f(1)*r.e[1] + (twoD ? Vec3::Zero() : Vec3(f(2)*r.e[2]));
        if (twoD) c.rts = f(1);
    }
    // converged: v* + M^-1 J^T r, momentum exactly consistent with the rows
    // (it differs from v by M^-1 grad l, within the tolerance); not
    // converged: the iterate v itself (its cost is below the warm start's),
    // since r(v) amplifies a velocity error e by 1/R_t (e/R_t: 5e5 e/W_nn
    // with beta 2e-3 and sigma 1e-3), which v* + M^-1 J^T r would turn into
    // velocities (measured: 8e4 m/s after a capped step of the landing column)
    const Eigen::VectorXd vEnd = converged ? Eigen::VectorXd(S.vStar + jr.cwiseQuotient(S.mass)) : S.v;
    const int NB = int(body.size());
    for (int b = 0; b < NB; ++b)
    {
        Body& B = body[b];
        if (S.tDof[b] >= 0)
            for (int a = 0; a < S.nt(); ++a) B.v(a) = vEnd(S.tDof[b] + a);
        if (S.rDof[b] >= 0)
        {
            if (twoD) B.w.z() = vEnd(S.rDof[b]);
            else for (int a = 0; a < 3; ++a) B.w(a) = vEnd(S.rDof[b] + a);
        }
    }
    // the common residual (ContactSolver.cpp), row by row into change
    double res2 = 0;
    for (SolverContact& c : rows)
    {
        const double r2 = localResidual2(c, c.rt, body[c.i], body[c.j], dt);
        res2 = std::max(res2, r2);
        c.change = std::sqrt(r2);
    }
    rep.sweeps = it;
    rep.localSolves = long(evals + it + 1)*long(NC);
    rep.linearIterations = cgIterations;
    rep.residual = dmin > 0 ? std::sqrt(res2)/dmin : 0.0;
    rep.converged = converged;
}

} // namespace nscd
