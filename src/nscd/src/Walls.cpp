// Triangulated walls: CGAL AABB tree of triangles, sphere range queries.
#include "SystemImpl.H"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

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
}

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
    auto P = [&](int k) { const Vec3& a = vertices[k]; return Point(a.x(), a.y(), a.z()); };
    for (const auto& f : tris) t->triangles.emplace_back(P(f[0]), P(f[1]), P(f[2]));
    t->tree.insert(t->triangles.begin(), t->triangles.end());
    t->tree.build();
    return t;
}

void trianglesNear(const TriangleTree& t, const Vec3& p, double R, std::vector<int>& out)
{
    out.clear();
    const K::Sphere_3 s(Point(p.x(), p.y(), p.z()), R*R);
    struct Out
    {
        std::vector<int>* o;
        Iterator begin;
        Out& operator=(const Primitive::Id& id) { o->push_back(int(id - begin)); return *this; }
        Out& operator*() { return *this; }
        Out& operator++() { return *this; }
        Out& operator++(int) { return *this; }
    };
    t.tree.all_intersected_primitives(s, Out{&out, t.triangles.begin()});
}

Vec3 closestPointTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1*d4 - d3*d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab*(d1/(d1 - d3));
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5*d2 - d1*d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac*(d2/(d2 - d6));
    const double va = d3*d6 - d5*d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return b + (c - b)*((d4 - d3)/((d4 - d3) + (d5 - d6)));
    const double denom = 1.0/(va + vb + vc);
    return a + ab*(vb*denom) + ac*(vc*denom);
}

} // namespace nscd
