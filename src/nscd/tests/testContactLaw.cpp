// SPDX-License-Identifier: GPL-3.0-or-later
// Contact kinematics (eq. 2.14-2.28) and local laws (eq. 2.37-2.41).
#include "nscd/ContactLaw.H"
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace nscd;

namespace
{
constexpr double pi = 3.14159265358979323846;
const double tight = 1e-12; // relative, round-off only

// Check the 2D law (eq. 2.37 with gap shift and cohesion c) for u+ = u + W r.
void expectLaw2D(const Eigen::Matrix2d& W, const Eigen::Vector2d& u, double mu, double c,
                 const Eigen::Vector2d& r, double tol)
{
    const Eigen::Vector2d up = u + W * r;
    const double rnt = r(0) + c;
    EXPECT_GE(rnt, -tol);
    EXPECT_GE(up(0), -tol);
    EXPECT_NEAR(rnt * up(0), 0.0, tol);
    EXPECT_LE(std::abs(r(1)), mu * rnt + tol);
    if (std::abs(up(1)) > tol)
    {
        EXPECT_NEAR(r(1), -mu * rnt * (up(1) > 0 ? 1 : -1), tol);
    }
}
} // namespace

// Reference: eq. 2.25-2.28 with disc inertia I = m r^2/2 (2D) and
// sphere inertia I = 2/5 m r^2: W_nn = 1/mA + 1/mB, W_tt = W_nn + rA^2/IA + rB^2/IB.
// Tolerance: 1e-12 relative (round-off).
TEST(Delassus, TwoEqualDiscsHeadOn)
{
    const double m = 2.5, r = 0.1, I = 0.5 * m * r * r;
    const Vec3 n(1, 0, 0), t(0, 1, 0), z(0, 0, 1);
    const Eigen::Matrix3d W = delassus(n, t, z, 1 / m, 1 / I, -r * n, 1 / m, 1 / I, r * n);
    EXPECT_NEAR(W(0, 0), 2 / m, tight * W(0, 0));
    EXPECT_NEAR(W(1, 1), 2 / m + 2 * r * r / I, tight * W(1, 1)); // = 6/m
    EXPECT_NEAR(W(1, 1), 6 / m, tight * W(1, 1));
    EXPECT_NEAR(W(0, 1), 0.0, tight);
    EXPECT_NEAR(W(1, 0), 0.0, tight);
}

TEST(Delassus, TwoEqualSpheresOblique)
{
    const double m = 1.3, r = 0.02, I = 0.4 * m * r * r;
    const Vec3 n = Vec3(1, 2, -0.5).normalized();
    const Vec3 s = n.unitOrthogonal(), t = n.cross(s);
    const Eigen::Matrix3d W = delassus(n, s, t, 1 / m, 1 / I, -r * n, 1 / m, 1 / I, r * n);
    EXPECT_NEAR(W(0, 0), 2 / m, tight * W(0, 0));
    EXPECT_NEAR(W(1, 1), 2 / m + 2 * r * r / I, tight * W(1, 1)); // = 7/m
    EXPECT_NEAR(W(2, 2), 7 / m, tight * W(2, 2));
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            if (a != b)
            {
                EXPECT_NEAR(W(a, b), 0.0, tight * W(0, 0));
            }
}

TEST(Delassus, DiscOnWallAndUnequalAndGeneralLever)
{
    // disc on a wall (infinite mass): W_nn = 1/m, W_tt = 1/m + r^2/I = 3/m
    const double m = 4.0, r = 0.5, I = 0.5 * m * r * r;
    const Vec3 n(0, 1, 0), t(-1, 0, 0), z(0, 0, 1);
    Eigen::Matrix3d W = delassus(n, t, z, 1 / m, 1 / I, -r * n, 0, 0, Vec3::Zero());
    EXPECT_NEAR(W(0, 0), 1 / m, tight);
    EXPECT_NEAR(W(1, 1), 3 / m, tight);
    // unequal discs
    const double m2 = 1.0, r2 = 0.2, I2 = 0.5 * m2 * r2 * r2;
    W = delassus(n, t, z, 1 / m, 1 / I, -r * n, 1 / m2, 1 / I2, r2 * n);
    EXPECT_NEAR(W(0, 0), 1 / m + 1 / m2, tight);
    EXPECT_NEAR(W(1, 1), 3 / m + 3 / m2, tight);
    // general lever (not along n): symmetric positive definite, couples n and t
    W = delassus(n, t, z, 1 / m, 1 / I, Vec3(0.1, -0.4, 0), 1 / m2, 1 / I2, Vec3(-0.05, 0.1, 0));
    EXPECT_NEAR((W - W.transpose()).norm(), 0.0, tight);
    EXPECT_GT(W.llt().info() == Eigen::Success ? 1 : 0, 0);
    EXPECT_GT(std::abs(W(0, 1)), 1e-3);
}

// Reference: eq. 2.38 (stick), 2.39 (slip forward, r_t = -mu r_n),
// 2.40 (slip backward), 2.41; exact arithmetic, tolerance 1e-12.
TEST(LocalSolver2D, StickSlipForwardBackwardSeparated)
{
    Eigen::Matrix2d W;
    W << 1.0, 0.0, 0.0, 3.0;
    const double mu = 0.5;
    Eigen::Vector2d r;
    // stick: r = -W^-1 u = (1, -1/30), inside the cone
    EXPECT_EQ(solveLocal2D(W, Eigen::Vector2d(-1, 0.1), mu, 0, r), ContactStatus::Stick);
    EXPECT_NEAR(r(0), 1.0, tight);
    EXPECT_NEAR(r(1), -0.1 / 3, tight);
    // slip forward: stick r_t = -2/3 < -mu r_n -> r_t = -0.5, u_t+ = 2 - 1.5 = 0.5 > 0
    EXPECT_EQ(solveLocal2D(W, Eigen::Vector2d(-1, 2), mu, 0, r), ContactStatus::SlipForward);
    EXPECT_NEAR(r(0), 1.0, tight);
    EXPECT_NEAR(r(1), -0.5, tight);
    expectLaw2D(W, Eigen::Vector2d(-1, 2), mu, 0, r, 1e-12);
    // slip backward
    EXPECT_EQ(solveLocal2D(W, Eigen::Vector2d(-1, -2), mu, 0, r), ContactStatus::SlipBackward);
    EXPECT_NEAR(r(1), 0.5, tight);
    // separated (approaching less than the gap allows: u~_n >= 0)
    EXPECT_EQ(solveLocal2D(W, Eigen::Vector2d(0.2, 5), mu, 0, r), ContactStatus::Separated);
    EXPECT_EQ(r(0), 0.0);
    EXPECT_EQ(r(1), 0.0);
    // cohesion c = 1: a separating velocity 0.5 < W_nn c is held (r_n = -0.5)
    EXPECT_EQ(solveLocal2D(W, Eigen::Vector2d(0.5, 0), mu, 1.0, r), ContactStatus::Stick);
    EXPECT_NEAR(r(0), -0.5, tight);
    // ... and a faster one breaks it (r_n = -c)
    EXPECT_EQ(solveLocal2D(W, Eigen::Vector2d(1.5, 0), mu, 1.0, r), ContactStatus::Separated);
    EXPECT_NEAR(r(0), -1.0, tight);
}

TEST(LocalSolver2D, CoupledDelassusSatisfiesLaw)
{
    // non-diagonal W (general lever arms): law checked on random inputs, tol 1e-10
    Eigen::Matrix2d W;
    W << 2.0, 0.6, 0.6, 3.0;
    std::mt19937 gen(3);
    std::uniform_real_distribution<double> U(-2, 2);
    for (int k = 0; k < 200; ++k)
    {
        const Eigen::Vector2d u(U(gen), U(gen));
        const double mu = 0.3 + 0.2 * std::abs(U(gen)), c = (k % 3 == 0) ? 0.3 : 0.0;
        Eigen::Vector2d r;
        solveLocal2D(W, u, mu, c, r);
        expectLaw2D(W, u, mu, c, r, 1e-10);
    }
}

TEST(LocalSolver, DiagonalVectorFormMatches2DAnd3D)
{
    // solveLocalDiagonal (hot loop) == solveLocal2D == solveLocal3D for diagonal W
    std::mt19937 gen(5);
    std::uniform_real_distribution<double> U(-2, 2);
    for (int k = 0; k < 200; ++k)
    {
        const double wnn = 1 + std::abs(U(gen)), wtt = 1 + 3 * std::abs(U(gen)), mu = 0.4;
        const double c = k % 2 ? 0.2 : 0.0;
        const Eigen::Vector2d u(U(gen), U(gen));
        Eigen::Matrix2d W;
        W << wnn, 0, 0, wtt;
        Eigen::Vector2d r2;
        solveLocal2D(W, u, mu, c, r2);
        double rn;
        Vec3 rt;
        solveLocalDiagonal(wnn, wtt, u(0), Vec3(0, u(1), 0), mu, c, rn, rt);
        EXPECT_NEAR(rn, r2(0), 1e-12);
        EXPECT_NEAR(rt.y(), r2(1), 1e-12);
        Eigen::Matrix3d W3 = Eigen::Vector3d(wnn, wtt, wtt).asDiagonal();
        Eigen::Vector3d r3 = Eigen::Vector3d::Zero();
        solveLocal3D(W3, Eigen::Vector3d(u(0), u(1), 0), mu, c, r3);
        EXPECT_NEAR(r3(0), r2(0), 1e-12);
        EXPECT_NEAR(r3(1), r2(1), 1e-12);
    }
}

TEST(LocalSolver3D, GeneralDelassusProjectedIteration)
{
    // coupled 3x3 W: fixed point on De Saxce's formulation; law checked to 1e-7
    Eigen::Matrix3d W;
    W << 2.0, 0.3, -0.2, 0.3, 3.0, 0.4, -0.2, 0.4, 2.5;
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> U(-2, 2);
    const double mu = 0.5;
    for (int k = 0; k < 100; ++k)
    {
        const Eigen::Vector3d u(U(gen), U(gen), U(gen));
        Eigen::Vector3d r = Eigen::Vector3d::Zero();
        solveLocal3D(W, u, mu, 0.0, r, 20000, 1e-14);
        const Eigen::Vector3d up = u + W * r;
        const double tn = std::hypot(r(1), r(2)), utn = std::hypot(up(1), up(2));
        EXPECT_GE(r(0), -1e-9);
        EXPECT_GE(up(0), -1e-7);
        EXPECT_NEAR(r(0) * up(0), 0.0, 1e-7);
        EXPECT_LE(tn, mu * r(0) + 1e-9);
        if (utn > 1e-6)
        {
            // slip: r_t = -mu r_n u_t/|u_t|
            EXPECT_NEAR(r(1), -mu * r(0) * up(1) / utn, 1e-6);
            EXPECT_NEAR(r(2), -mu * r(0) * up(2) / utn, 1e-6);
        }
    }
}

// Reference: exact exponential map, rotation angle = |omega| t, |q| = 1 (1e-12).
// Half-angles per step |omega| dt/2 of 1.1e-3-1.3e-3 (the series branch of the
// update, below 5e-3) and of 1.1e-2-1.3e-2 (sin and cos).
TEST(Quaternion, ConstantOmegaSphereAndDisc)
{
    for (int dim : {3, 2})
        for (const double dt : {1e-3, 1e-2})
        {
            System s(dim);
            const int m = s.addMaterial({1000, 0.5});
            s.addGrain(Vec3(0, 0, 0), 0.1, m);
            const Vec3 w = dim == 3 ? Vec3(1.0, -2.0, 0.5) : Vec3(0, 0, 2.5);
            s.angularVelocities()[0] = w;
            const int n = int(std::lround(1.0 / dt));
            for (int k = 0; k < n; ++k) s.step(dt);
            const Eigen::Quaterniond& q = s.orientations()[0];
            EXPECT_NEAR(q.norm(), 1.0, 1e-14);
            const Eigen::AngleAxisd aa(q);
            const double expected = std::fmod(w.norm() * n * dt, 2 * pi);
            EXPECT_NEAR(aa.angle(), expected, 1e-10);
            EXPECT_NEAR(std::abs(aa.axis().dot(w.normalized())), 1.0, 1e-12);
            EXPECT_EQ(s.angularVelocities()[0], w); // free sphere: omega constant
        }
}
