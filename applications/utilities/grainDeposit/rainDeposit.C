// SPDX-License-Identifier: GPL-3.0-or-later
#include "rainDeposit.H"

#include <algorithm>
#include <cmath>
#include <limits>

namespace
{

struct disc { double x, y, r; };

//- What stopped a disc rolling over another one
enum class stop { none, floorOrWall, disc };

//- Uniform grid of square cells of side h over [x0, x0 + nx h] x [y0, ...),
//  rows added as the deposit grows
class rainGrid
{
    double x0_, y0_, h_;
    int nx_;
    std::vector<std::vector<int>> cells_;   // row-major, nx_ per row

public:
    rainGrid(double x0, double y0, double h, int nx)
    :
        x0_(x0), y0_(y0), h_(h), nx_(nx)
    {}

    int col(double x) const
    {
        return std::min(nx_ - 1, std::max(0, int(std::floor((x - x0_)/h_))));
    }
    int row(double y) const
    {
        return std::max(0, int(std::floor((y - y0_)/h_)));
    }
    int rows() const { return int(cells_.size())/nx_; }

    void add(int id, double x, double y)
    {
        const int r = row(y);
        if (r >= rows()) cells_.resize(std::size_t(r + 1)*nx_);
        cells_[std::size_t(r)*nx_ + col(x)].push_back(id);
    }

    //- Calls f(id) for the discs of columns [c0, c1], rows [r0, r1]
    template<class F>
    void visit(int c0, int c1, int r0, int r1, F f) const
    {
        c0 = std::max(0, c0);
        c1 = std::min(nx_ - 1, c1);
        r0 = std::max(0, r0);
        r1 = std::min(rows() - 1, r1);
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c)
                for (int id : cells_[std::size_t(r)*nx_ + c]) f(id);
    }
};


class rainModel
{
    const double x0_, x1_, y0_, h_;
    std::vector<disc> d_;
    rainGrid grid_;

public:
    rainModel(double x0, double x1, double y0, double dMax)
    :
        x0_(x0), x1_(x1), y0_(y0), h_(dMax),
        grid_(x0, y0, dMax, std::max(1, int(std::ceil((x1 - x0)/dMax))))
    {}

    const std::vector<disc>& discs() const { return d_; }

    //- Highest centre height <= yStart [m] at which a disc of radius r
    //  falling at abscissa x first touches a laid disc (not `exclude`) or
    //  the floor; sets `support` (-1: the floor)
    double land
    (
        double x,
        double r,
        double yStart,
        int exclude,
        int& support
    ) const
    {
        double best = y0_ + r;
        support = -1;
        const int c = grid_.col(x);
        const int rTop =
            std::isfinite(yStart) ? grid_.row(yStart) + 1 : grid_.rows() - 1;
        grid_.visit(c - 1, c + 1, 0, rTop, [&](int k)
        {
            if (k == exclude) return;
            const double R = r + d_[k].r, dx = x - d_[k].x;
            if (std::abs(dx) >= R*(1 - 1e-12)) return;
            const double yc = d_[k].y + std::sqrt(R*R - dx*dx);
            if (yc <= yStart + 1e-12*R && yc > best) { best = yc; support = k; }
        });
        return best;
    }

    //- Rolls a disc of radius r touching disc j at (px, py) over j towards
    //  side s (+1: +x) until it touches the floor, a wall or another disc k
    //  (returned, with the point), or reaches j's level (stop::none,
    //  point at the level)
    stop roll(int j, double r, int s, double& px, double& py, int& k) const
    {
        const disc& J = d_[j];
        const double R = r + J.r;
        const double t0 = std::atan2(py - J.y, px - J.x);
        const double length = s > 0 ? t0 : M_PI - t0;
        k = -1;
        stop what = stop::none;
        double first = length;
        double angle = s > 0 ? 0.0 : M_PI;
        auto consider = [&](double phi, stop type, int id)
        {
            if (phi < -0.5*M_PI) phi += 2*M_PI;
            const double p = s > 0 ? t0 - phi : phi - t0;
            if (p > 1e-12 && p < first)
            {
                first = p;
                angle = phi;
                what = type;
                k = id;
            }
        };
        if (length > 0)
        {
            // the side walls and the floor, for the centre: x = x0 + r,
            // x = x1 - r, y = y0 + r
            for (double xw : {x0_ + r, x1_ - r})
            {
                const double c = (xw - J.x)/R;
                if (std::abs(c) <= 1)
                    consider(std::acos(c), stop::floorOrWall, -1);
            }
            const double sn = (y0_ + r - J.y)/R;
            if (std::abs(sn) <= 1)
            {
                consider(std::asin(sn), stop::floorOrWall, -1);
                consider(M_PI - std::asin(sn), stop::floorOrWall, -1);
            }
            const int c = grid_.col(J.x), rr = grid_.row(J.y);
            grid_.visit(c - 2, c + 2, rr - 2, rr + 2, [&](int id)
            {
                if (id == j) return;
                const disc& K = d_[id];
                const double Rk = r + K.r;
                const double dx = K.x - J.x, dy = K.y - J.y;
                const double dd = std::hypot(dx, dy);
                if (dd >= R + Rk || dd <= std::abs(R - Rk)) return;
                const double a = (R*R - Rk*Rk + dd*dd)/(2*dd);
                const double hh = std::sqrt(std::max(0.0, R*R - a*a));
                const double bx = a*dx/dd, by = a*dy/dd;
                consider
                (
                    std::atan2(by + hh*dx/dd, bx - hh*dy/dd), stop::disc, id
                );
                consider
                (
                    std::atan2(by - hh*dx/dd, bx + hh*dy/dd), stop::disc, id
                );
            });
        }
        else
        {
            what = stop::none;
            angle = t0;
        }
        px = J.x + R*std::cos(angle);
        py = J.y + R*std::sin(angle);
        return what;
    }

    //- Drops a disc of radius r at abscissa x and rolls it to rest; lays it
    void lay(double x, double r, std::mt19937_64& rng)
    {
        int support = -1;
        double y =
            land(x, r, std::numeric_limits<double>::infinity(), -1, support);
        std::uniform_int_distribution<int> side(0, 1);
        for (int n = 0; n < 100000 && support >= 0; ++n)
        {
            const int j = support;
            const int s =
                x > d_[j].x ? 1 : x < d_[j].x ? -1 : (side(rng) ? 1 : -1);
            int k = -1;
            const stop what = roll(j, r, s, x, y, k);
            if (what == stop::floorOrWall) break;
            if (what == stop::none)
            {
                // off j's side: falls vertically from there
                x = std::min(x1_ - r, std::max(x0_ + r, x));
                y = land(x, r, y, j, support);
                continue;
            }
            // on j and k: at rest if its centre is between theirs
            const double lo = std::min(d_[j].x, d_[k].x),
                hi = std::max(d_[j].x, d_[k].x);
            if (x >= lo && x <= hi) break;
            // else it rolls on over the outer one of the two
            support = x < lo
              ? (d_[j].x < d_[k].x ? j : k)
              : (d_[j].x > d_[k].x ? j : k);
        }
        grid_.add(int(d_.size()), x, y);
        d_.push_back({x, y, r});
    }
};

} // End anonymous namespace


std::vector<Foam::grainSpec> Foam::rainDeposit
(
    const double x0,
    const double x1,
    const double y0,
    const std::vector<double>& diameters,
    std::mt19937_64& rng
)
{
    double dMax = 0;
    for (double d : diameters) dMax = std::max(dMax, d);
    std::vector<grainSpec> out;
    if (diameters.empty()) return out;
    rainModel model(x0, x1, y0, dMax);
    std::uniform_real_distribution<double> uni(0, 1);
    for (double d : diameters)
    {
        const double r = 0.5*d;
        model.lay(x0 + r + (x1 - x0 - d)*uni(rng), r, rng);
    }
    for (const disc& q : model.discs())
    {
        out.push_back({nscd::Vec3(q.x, q.y, 0), 2*q.r});
    }
    return out;
}
