// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file MeshBuilders.cpp
 */
#include "overlapMapping/MeshBuilders.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace overlapMapping
{

std::vector<std::vector<label>> cellModelFaces(CellShape shape, const std::vector<label>& v)
{
    auto F = [&](std::initializer_list<int> ids)
    {
        std::vector<label> f;
        for (int i : ids)
        {
            f.push_back(v.at(i));
        }
        return f;
    };
    switch (shape)
    {
    case CellShape::Tet:
        return {F({1, 2, 3}), F({0, 3, 2}), F({0, 1, 3}), F({0, 2, 1})};
    case CellShape::Prism:
        return {F({0, 2, 1}), F({3, 4, 5}), F({0, 3, 5, 2}), F({1, 2, 5, 4}), F({0, 1, 4, 3})};
    case CellShape::Hex:
        return {F({0, 4, 7, 3}), F({1, 2, 6, 5}), F({0, 1, 5, 4}),
                F({3, 7, 6, 2}), F({0, 3, 2, 1}), F({4, 5, 6, 7})};
    default:
        throw std::invalid_argument("overlapMapping::cellModelFaces: polyhedra have no model faces");
    }
}

MeshView meshFromCellFaces(const std::vector<Vec3>& points,
                           const std::vector<std::vector<std::vector<label>>>& cells)
{
    MeshView m;
    m.points = points;
    std::map<std::vector<label>, label> known;
    for (label c = 0; c < label(cells.size()); ++c)
    {
        for (const auto& f : cells[c])
        {
            std::vector<label> key = f;
            std::sort(key.begin(), key.end());
            auto it = known.find(key);
            if (it == known.end())
            {
                known.emplace(std::move(key), m.addFace(f, c, -1));
            }
            else
            {
                const label fi = it->second;
                if (m.neighbour[fi] >= 0)
                {
                    throw std::invalid_argument("overlapMapping::meshFromCellFaces: face shared by more "
                                                "than two cells");
                }
                m.neighbour[fi] = c;
            }
        }
    }
    computeCellGeometry(m);
    return m;
}

namespace
{

struct Grid
{
    std::vector<Vec3> pts;
    label nx, ny, nz;
    label id(label i, label j, label k) const { return i + (nx + 1) * (j + (ny + 1) * k); }
    std::vector<label> hex(label i, label j, label k) const
    {
        return {id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),     id(i, j + 1, k),
                id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
    }
};

Grid makeGrid(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs,
              const PointMap& map)
{
    if (xs.size() < 2 || ys.size() < 2 || zs.size() < 2)
    {
        throw std::invalid_argument("overlapMapping mesh builders: need at least 2 coordinates per axis");
    }
    Grid g;
    g.nx = label(xs.size()) - 1;
    g.ny = label(ys.size()) - 1;
    g.nz = label(zs.size()) - 1;
    g.pts.reserve(xs.size() * ys.size() * zs.size());
    for (double z : zs)
        for (double y : ys)
            for (double x : xs)
            {
                Vec3 p(x, y, z);
                g.pts.push_back(map ? map(p) : p);
            }
    return g;
}

/// Tet faces with positive orientation enforced.
std::vector<std::vector<label>> tetFaces(const std::vector<Vec3>& P, label a, label b, label c, label d)
{
    if ((P[b] - P[a]).cross(P[c] - P[a]).dot(P[d] - P[a]) < 0.0)
    {
        std::swap(b, c);
    }
    return cellModelFaces(CellShape::Tet, {a, b, c, d});
}

} // namespace

MeshView hexGridMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<double>& zs, const PointMap& map)
{
    const Grid g = makeGrid(xs, ys, zs, map);
    std::vector<std::vector<std::vector<label>>> cells;
    cells.reserve(size_t(g.nx) * g.ny * g.nz);
    for (label k = 0; k < g.nz; ++k)
        for (label j = 0; j < g.ny; ++j)
            for (label i = 0; i < g.nx; ++i) cells.push_back(cellModelFaces(CellShape::Hex, g.hex(i, j, k)));
    return meshFromCellFaces(g.pts, cells);
}

MeshView tetGridMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<double>& zs, int tetsPerHex, const PointMap& map)
{
    if (tetsPerHex != 5 && tetsPerHex != 6)
    {
        throw std::invalid_argument("overlapMapping::tetGridMesh: tetsPerHex must be 5 or 6");
    }
    const Grid g = makeGrid(xs, ys, zs, map);
    static const int six[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6},
                                  {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
    static const int fiveEven[5][4] = {{0, 1, 2, 5}, {0, 2, 7, 5}, {0, 2, 3, 7}, {0, 5, 7, 4}, {2, 7, 5, 6}};
    static const int fiveOdd[5][4] = {{1, 3, 4, 6}, {0, 1, 3, 4}, {1, 2, 3, 6}, {1, 4, 5, 6}, {3, 4, 6, 7}};
    std::vector<std::vector<std::vector<label>>> cells;
    for (label k = 0; k < g.nz; ++k)
        for (label j = 0; j < g.ny; ++j)
            for (label i = 0; i < g.nx; ++i)
            {
                const auto h = g.hex(i, j, k);
                if (tetsPerHex == 6)
                {
                    for (const auto& t : six)
                        cells.push_back(tetFaces(g.pts, h[t[0]], h[t[1]], h[t[2]], h[t[3]]));
                }
                else
                {
                    const auto& T = ((i + j + k) % 2 == 0) ? fiveEven : fiveOdd;
                    for (const auto& t : T)
                        cells.push_back(tetFaces(g.pts, h[t[0]], h[t[1]], h[t[2]], h[t[3]]));
                }
            }
    return meshFromCellFaces(g.pts, cells);
}

MeshView prismGridMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                       const std::vector<double>& zs, const PointMap& map)
{
    const Grid g = makeGrid(xs, ys, zs, map);
    std::vector<std::vector<std::vector<label>>> cells;
    for (label k = 0; k < g.nz; ++k)
        for (label j = 0; j < g.ny; ++j)
            for (label i = 0; i < g.nx; ++i)
            {
                const auto h = g.hex(i, j, k);
                cells.push_back(cellModelFaces(CellShape::Prism, {h[0], h[1], h[2], h[4], h[5], h[6]}));
                cells.push_back(cellModelFaces(CellShape::Prism, {h[0], h[2], h[3], h[4], h[6], h[7]}));
            }
    return meshFromCellFaces(g.pts, cells);
}

MeshView grid2DMesh(const std::vector<double>& xs, const std::vector<double>& ys, double z0, double z1,
                    bool triangles, const PointMap& map)
{
    PointMap m2 = nullptr;
    if (map)
    {
        m2 = [&map](const Vec3& p)
        {
            Vec3 q = map(p);
            q[2] = p[2];
            return q;
        };
    }
    MeshView m = triangles ? prismGridMesh(xs, ys, {z0, z1}, m2) : hexGridMesh(xs, ys, {z0, z1}, m2);
    m.twoD = true;
    m.z0 = z0;
    m.z1 = z1;
    return m;
}

std::vector<double> gradedSpacing(double a, double b, int n, double ratio)
{
    if (n < 1)
    {
        throw std::invalid_argument("overlapMapping::gradedSpacing: n must be >= 1");
    }
    std::vector<double> x(n + 1);
    const double q = n > 1 ? std::pow(ratio, 1.0 / (n - 1)) : 1.0;
    double sum = 0.0, w = 1.0;
    std::vector<double> d(n);
    for (int i = 0; i < n; ++i)
    {
        d[i] = w;
        sum += w;
        w *= q;
    }
    x[0] = a;
    for (int i = 0; i < n; ++i)
    {
        x[i + 1] = x[i] + (b - a) * d[i] / sum;
    }
    x[n] = b;
    return x;
}

} // namespace overlapMapping
