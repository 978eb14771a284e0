// SPDX-License-Identifier: GPL-3.0-or-later
#include "nscd/ContactLaw.H"

namespace nscd
{

Eigen::Matrix3d skew(const Vec3& a)
{
    // eq. 2.17: R = [0 z -y; -z 0 x; y -x 0], R^T w = w x a
    Eigen::Matrix3d R;
    R << 0.0, a.z(), -a.y(), -a.z(), 0.0, a.x(), a.y(), -a.x(), 0.0;
    return R;
}

Eigen::Matrix3d delassus(const Vec3& n, const Vec3& s, const Vec3& t, double invMassA, double invInertiaA,
                         const Vec3& leverA, double invMassB, double invInertiaB, const Vec3& leverB)
{
    Eigen::Matrix3d B;
    B.col(0) = n;
    B.col(1) = s;
    B.col(2) = t;
    auto part = [&](double im, double ii, const Vec3& a)
    {
        // H = [I; R] B (eq. 2.20), W = H^T M^-1 H (eq. 2.25)
        Eigen::Matrix<double, 6, 3> H;
        H.topRows<3>() = B;
        H.bottomRows<3>() = skew(a) * B;
        Eigen::Matrix<double, 6, 6> Minv = Eigen::Matrix<double, 6, 6>::Zero();
        Minv.topLeftCorner<3, 3>().diagonal().setConstant(im);
        Minv.bottomRightCorner<3, 3>().diagonal().setConstant(ii);
        return Eigen::Matrix3d(H.transpose() * Minv * H);
    };
    // eq. 2.28: W = W_A + W_B
    return part(invMassA, invInertiaA, leverA) + part(invMassB, invInertiaB, leverB);
}

ContactStatus solveLocal2D(const Eigen::Matrix2d& W, const Eigen::Vector2d& u, double mu, double c,
                           Eigen::Vector2d& r)
{
    // Separation: r~ = 0, i.e. r = (-c, 0); admissible if u~_n^+ >= 0.
    if (u(0) - W(0, 0) * c >= 0.0)
    {
        r << -c, 0.0;
        return ContactStatus::Separated;
    }
    // Stick impulse (eq. 2.38): r = -W^-1 u~
    const double det = W(0, 0) * W(1, 1) - W(0, 1) * W(1, 0);
    Eigen::Vector2d rs;
    rs(0) = -(W(1, 1) * u(0) - W(0, 1) * u(1)) / det;
    rs(1) = -(-W(1, 0) * u(0) + W(0, 0) * u(1)) / det;
    const double rnt = rs(0) + c;
    if (rnt >= 0.0 && std::abs(rs(1)) <= mu * rnt)
    {
        r = rs;
        return ContactStatus::Stick;
    }
    // Slip (eq. 2.39-2.40): r_t = sigma mu r~_n, sigma from the stick solution
    const double sigma = rs(1) > 0.0 ? 1.0 : -1.0;
    // eq. 2.41, normal row: 0 = u~_n + W_nn r_n + W_nt sigma mu (r_n + c)
    const double rn = -(u(0) + W(0, 1) * sigma * mu * c) / (W(0, 0) + sigma * mu * W(0, 1));
    if (rn + c <= 0.0)
    {
        r << -c, 0.0;
        return ContactStatus::Separated;
    }
    r << rn, sigma * mu * (rn + c);
    return sigma < 0 ? ContactStatus::SlipForward : ContactStatus::SlipBackward;
}

namespace
{
// Projection onto the cone K = {|r_t| <= mu r_n} (local frame (n, s, t)).
Eigen::Vector3d projectCone(const Eigen::Vector3d& r, double mu)
{
    const double rn = r(0);
    const double rtn = std::hypot(r(1), r(2));
    if (rtn <= mu * rn) return r;
    if (mu * rtn <= -rn) return Eigen::Vector3d::Zero();
    const double pn = (rn + mu * rtn) / (1.0 + mu * mu);
    Eigen::Vector3d p;
    p(0) = pn;
    p(1) = mu * pn * r(1) / rtn;
    p(2) = mu * pn * r(2) / rtn;
    return p;
}
} // namespace

ContactStatus solveLocal3D(const Eigen::Matrix3d& W, const Eigen::Vector3d& u, double mu, double c,
                           Eigen::Vector3d& r, int maxIter, double tol)
{
    const double scale = W.diagonal().cwiseAbs().maxCoeff();
    const double eps = 1e-14 * scale;
    const bool diagonal = std::abs(W(0, 1)) <= eps && std::abs(W(0, 2)) <= eps && std::abs(W(1, 2)) <= eps
                          && std::abs(W(1, 0)) <= eps && std::abs(W(2, 0)) <= eps && std::abs(W(2, 1)) <= eps
                          && std::abs(W(1, 1) - W(2, 2)) <= eps;
    if (diagonal)
    {
        double rn;
        Vec3 rt;
        const Vec3 ut(0.0, u(1), u(2));
        const ContactStatus st = solveLocalDiagonal(W(0, 0), W(1, 1), u(0), ut, mu, c, rn, rt);
        r << rn, rt(1), rt(2);
        return st;
    }
    // General case: fixed point on r~ = r + c e_n with De Saxce's modified velocity.
    Eigen::Vector3d rt = r;
    rt(0) += c;
    const Eigen::Vector3d u0 = u - c * W.col(0); // u+ = u0 + W r~
    const double rho = 1.0 / scale;
    for (int k = 0; k < maxIter; ++k)
    {
        Eigen::Vector3d up = u0 + W * rt;
        up(0) += mu * std::hypot(up(1), up(2));
        const Eigen::Vector3d rn = projectCone(rt - rho * up, mu);
        const double d = (rn - rt).norm();
        rt = rn;
        if (d <= tol * std::max(rt.norm(), 1e-300)) break;
    }
    r = rt;
    r(0) -= c;
    const double tn = std::hypot(rt(1), rt(2));
    if (rt(0) <= 1e-14 * std::max(1.0, std::abs(c))) return ContactStatus::Separated;
    if (tn < mu * rt(0) * (1.0 - 1e-9)) return ContactStatus::Stick;
    return ContactStatus::Slip;
}

} // namespace nscd
