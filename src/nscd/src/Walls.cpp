// SPDX-License-Identifier: GPL-3.0-or-later
// Triangulated walls: CGAL AABB tree of triangles, sphere range queries.
#include "SystemImpl.H"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace nscd
{

namespace
{
using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Triangle = K::Triangle_3;
using Iterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Traits = CGAL::AABB_traits<K, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;
} // namespace

struct TriangleTree
{
    std::vector<Triangle> triangles;
    Tree tree;
};

std::shared_ptr<TriangleTree> buildTriangleTree(const std::vector<Vec3>& vertices,
                                                const std::vector<std::array<int, 3>>& tris)
{
    auto t = std::make_shared<TriangleTree>();
    t->triangles.reserve(tris.size());
    auto P = [&](int k)
    {
        const Vec3& a = vertices[k];
        return Point(a.x(), a.y(), a.z());
    };
    for (const auto& f : tris) t->triangles.emplace_back(P(f[0]), P(f[1]), P(f[2]));
    t->tree.insert(t->triangles.begin(), t->triangles.end());
    t->tree.build();
    return t;
}

void trianglesNear(const TriangleTree& t, const Vec3& p, double R, std::vector<int>& out)
{
    out.clear();
    const K::Sphere_3 s(Point(p.x(), p.y(), p.z()), R * R);
    struct Out
    {
        std::vector<int>* o;
        Iterator begin;
        Out& operator=(const Primitive::Id& id)
        {
            o->push_back(int(id - begin));
            return *this;
        }
        Out& operator*() { return *this; }
        Out& operator++() { return *this; }
        Out& operator++(int) { return *this; }
    };
    t.tree.all_intersected_primitives(s, Out{&out, t.triangles.begin()});
}

Vec3 closestPointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int& feature)
{
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0)
    {
        feature = 0;
        return a;
    }
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
    {
        feature = 1;
        return b;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
    {
        feature = 3;
        return a + ab * (d1 / (d1 - d3));
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
    {
        feature = 2;
        return c;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
    {
        feature = 5;
        return a + ac * (d2 / (d2 - d6));
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    {
        feature = 4;
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    feature = -1;
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

Vec3 closestPointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
    int f;
    return closestPointTriangle(p, a, b, c, f);
}

void buildTriangleFeatures(Wall& w)
{
    const std::size_t nt = w.triangles.size();
    const double cosFlat = std::cos(flatAngle);
    w.triNormal.assign(nt, Vec3::Zero());
    w.triFlat.assign(nt, 0);
    for (std::size_t t = 0; t < nt; ++t)
    {
        const auto& f = w.triangles[t];
        const Vec3 n = (w.vertices[f[1]] - w.vertices[f[0]]).cross(w.vertices[f[2]] - w.vertices[f[0]]);
        const double nn = n.norm();
        if (nn > 0 && std::isfinite(nn)) w.triNormal[t] = n / nn;
    }
    // edges by sorted vertex pair: (key, triangle, local edge)
    struct E
    {
        long long key;
        int t;
        int e;
    };
    std::vector<E> edges;
    edges.reserve(3 * nt);
    const long long nv = (long long)w.vertices.size();
    for (std::size_t t = 0; t < nt; ++t)
        for (int e = 0; e < 3; ++e)
        {
            const long long a = w.triangles[t][e], b = w.triangles[t][(e + 1) % 3];
            edges.push_back({std::min(a, b) * nv + std::max(a, b), int(t), e});
        }
    std::sort(edges.begin(), edges.end(), [](const E& x, const E& y) { return x.key < y.key; });
    // vertex v is flat unless some incident edge is not flat (boundary, fold,
    // crease) or an incident triangle is not coplanar with the first one
    std::vector<char> vertBad(w.vertices.size(), 0);
    std::vector<int> vertTri(w.vertices.size(), -1);
    for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k)
        {
            const int v = w.triangles[t][k];
            if (w.triNormal[t].isZero())
            {
                vertBad[v] = 1;
                continue;
            }
            if (vertTri[v] < 0)
                vertTri[v] = int(t);
            else if (std::abs(w.triNormal[t].dot(w.triNormal[vertTri[v]])) < cosFlat)
                vertBad[v] = 1;
        }
    for (std::size_t k = 0; k < edges.size();)
    {
        std::size_t l = k + 1;
        while (l < edges.size() && edges[l].key == edges[k].key) ++l;
        bool flat = false;
        if (l - k == 2)
        {
            const E& A = edges[k];
            const E& B = edges[k + 1];
            const Vec3& na = w.triNormal[A.t];
            const Vec3& nb = w.triNormal[B.t];
            if (!na.isZero() && !nb.isZero() && std::abs(na.dot(nb)) >= cosFlat)
            {
                // the two triangles lie on either side of the edge
                const auto& fa = w.triangles[A.t];
                const auto& fb = w.triangles[B.t];
                const Vec3 p = w.vertices[fa[A.e]];
                const Vec3 d = (w.vertices[fa[(A.e + 1) % 3]] - p).normalized();
                Vec3 ua = w.vertices[fa[(A.e + 2) % 3]] - p;
                Vec3 ub = w.vertices[fb[(B.e + 2) % 3]] - p;
                ua -= ua.dot(d) * d;
                ub -= ub.dot(d) * d;
                flat = ua.dot(ub) < 0;
            }
        }
        for (std::size_t m = k; m < l; ++m)
        {
            const E& X = edges[m];
            if (flat)
                w.triFlat[X.t] |= (unsigned char)(1u << X.e);
            else
            {
                vertBad[w.triangles[X.t][X.e]] = 1;
                vertBad[w.triangles[X.t][(X.e + 1) % 3]] = 1;
            }
        }
        k = l;
    }
    for (std::size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k)
            if (!vertBad[w.triangles[t][k]]) w.triFlat[t] |= (unsigned char)(1u << (3 + k));
}

void linkSegment(std::vector<Wall>& walls, int k)
{
    Wall& S = walls[k];
    if (S.type != SegmentWall) return;
    const double cosFlat = std::cos(flatAngle);
    const Vec3 sa = S.p + S.displacement, sb = S.b + S.displacement;
    const double ls = (sb - sa).norm();
    const Vec3 ends[2] = {sa, sb};
    for (int o = 0; o < k; ++o)
    {
        Wall& T = walls[o];
        if (T.type != SegmentWall) continue;
        const Vec3 ta = T.p + T.displacement, tb = T.b + T.displacement;
        const double lt = (tb - ta).norm();
        const double tol = 1e-9 * std::min(ls, lt);
        const Vec3 tends[2] = {ta, tb};
        for (int e = 0; e < 2; ++e)
            for (int f = 0; f < 2; ++f)
            {
                if ((ends[e] - tends[f]).norm() > tol) continue;
                // directions pointing away from the shared point
                const Vec3 ds = (ends[1 - e] - ends[e]) / ls;
                const Vec3 dt = (tends[1 - f] - tends[f]) / lt;
                const bool flat = ds.dot(dt) <= -cosFlat;
                // keep the first neighbour found, but prefer a collinear one
                if (S.segNb[e] < 0 || (flat && !S.segFlat[e]))
                {
                    S.segNb[e] = o;
                    S.segFlat[e] = flat;
                }
                if (T.segNb[f] < 0 || (flat && !T.segFlat[f]))
                {
                    T.segNb[f] = k;
                    T.segFlat[f] = flat;
                }
            }
    }
}

} // namespace nscd
