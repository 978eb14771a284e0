// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file CellMesh.hpp
 * @brief Mesh prepared for overlap computations: cell adjacency, bounding
 *        spheres, 2D polygons, 3D element shapes, point location.
 */
#ifndef OVERLAPMAPPING_CELLMESH_HPP
#define OVERLAPMAPPING_CELLMESH_HPP

#include "overlapMapping/MeshView.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace overlapMapping
{

/**
 * @brief Shape of a 3D cell as recognised for the `overlap` library.
 *
 * Vertex orderings (CellMesh::shapeVertices) follow OpenFOAM's cellModels,
 * which are identical to the `overlap` library's (checked in
 * tests/testGeometry3D.cpp):
 *  - Tet: (0,1,2) oriented with its right-hand normal towards vertex 3;
 *  - Prism (OpenFOAM "prism", overlap "Wedge"): bottom triangle 0,1,2
 *    (normal towards the top), top 3,4,5 with 3 above 0, 4 above 1, 5 above 2;
 *  - Hex: blockMesh order, bottom 0,1,2,3 counter-clockwise seen from the top,
 *    top 4,5,6,7 with 4 above 0 etc.
 * Polyhedron: anything else, or a tet/prism/hex with a warped face; it is
 * decomposed into tetrahedra (cell centre, face centre, edge).
 */
enum class CellShape : std::uint8_t
{
    Tet,
    Prism,
    Hex,
    Polyhedron
};

/**
 * @brief Mesh prepared for overlap queries (immutable after construction).
 *
 * Copies the MeshView it is built from (so the view may be discarded) and
 * precomputes: face centres/unit normals, the cell-to-cell adjacency through
 * internal faces, a bounding sphere per cell (centre = cell centre, radius =
 * farthest vertex), 2D polygons (counter-clockwise, with edge normals and edge
 * neighbours) or 3D element shapes, and a uniform bin grid for point location.
 * Cost O(nCells) time and memory.
 */
class CellMesh
{
public:
    /**
     * @brief Prepare @p mesh.
     * @throws std::invalid_argument if the connectivity is inconsistent
     *         (sizes, indices out of range), if a 2D mesh cell has no face on
     *         the back plane, or if a cell has a non-positive volume.
     */
    explicit CellMesh(MeshView mesh);

    /// The (completed) mesh view: cells, centres and volumes are filled.
    const MeshView& view() const { return mesh_; }

    /// Number of cells.
    label nCells() const { return nCells_; }
    /// True for a one-cell-thick 2D mesh.
    bool twoD() const { return mesh_.twoD; }
    /// Depth z1 - z0 of a 2D mesh [m] (0 in 3D).
    double depth() const { return depth_; }
    /// Back plane z0 of a 2D mesh [m].
    double z0() const { return mesh_.z0; }
    /// Front plane z1 of a 2D mesh [m].
    double z1() const { return mesh_.z1; }

    /// Cell centre [m] (as given by / computed into the view).
    const Vec3& cellCentre(label c) const { return mesh_.cellCentres[c]; }
    /// Cell volume [m^3] (as given by / computed into the view).
    double cellVolume(label c) const { return mesh_.cellVolumes[c]; }
    /// Bounding sphere centre (2D: polygon centroid at mid depth) [m].
    const Vec3& boundCentre(label c) const { return boundCentre_[c]; }
    /// Bounding sphere radius (2D: bounding circle radius in xy) [m].
    double boundRadius(label c) const { return boundRadius_[c]; }

    /// Cells sharing an internal face with @p c: [begin, end).
    const label* neighboursBegin(label c) const { return adjCells_.data() + adjOffsets_[c]; }
    /// End of the neighbour list of @p c.
    const label* neighboursEnd(label c) const { return adjCells_.data() + adjOffsets_[c + 1]; }

    // ---- 2D -------------------------------------------------------------
    /// Number of polygon vertices of 2D cell @p c.
    int polygonSize(label c) const { return polyOffsets_[c + 1] - polyOffsets_[c]; }
    /// Polygon vertices (xy, counter-clockwise) of 2D cell @p c.
    const Vec2* polygon(label c) const { return polyVerts_.data() + polyOffsets_[c]; }
    /// Outward unit normals of the polygon edges (edge k from vertex k to k+1).
    const Vec2* edgeNormals(label c) const { return edgeNormal_.data() + polyOffsets_[c]; }
    /// n_k . a_k for each edge (signed distance of x = n.x - offset).
    const double* edgeOffsets(label c) const { return edgeOffset_.data() + polyOffsets_[c]; }
    /// Polygon area [m^2] of 2D cell @p c.
    double polygonArea(label c) const { return polyArea_[c]; }
    /// Polygon centroid [m] of 2D cell @p c.
    const Vec2& polygonCentroid(label c) const { return polyCentroid_[c]; }

    // ---- 3D -------------------------------------------------------------
    /// Shape of 3D cell @p c.
    CellShape shape(label c) const { return shape_[c]; }
    /// 8 vertex indices (unused slots -1) in the order of CellShape.
    const label* shapeVertices(label c) const { return shapeVerts_.data() + 8 * c; }
    /// Volume consistent with the overlap computation (box volume for box
    /// cells, overlap library element volume for other tet/prism/hex, sum of
    /// the decomposition tets otherwise).
    double shapeVolume(label c) const { return shapeVolume_[c]; }
    /**
     * @brief True if 3D cell @p c is an axis-aligned box (a hex with
     *        axis-aligned faces, possibly split by hanging vertices; detected
     *        by axisAlignedBoxCell() in SphereBox.hpp with a tolerance of
     *        1e-12 x the cell size); its overlaps then use the closed form
     *        sphereBoxOverlap(). False in 2D.
     */
    bool isBox(label c) const { return !boxIndex_.empty() && boxIndex_[c] >= 0; }
    /// Lower corner of box cell @p c [m] (only if isBox(c)).
    const Vec3& boxMin(label c) const { return boxLo_[boxIndex_[c]]; }
    /// Upper corner of box cell @p c [m] (only if isBox(c)).
    const Vec3& boxMax(label c) const { return boxHi_[boxIndex_[c]]; }
    /// True if every vertex lies on the inner side of every face plane
    /// (within round-off): a sphere then lies inside the cell iff its centre is
    /// at least r from every face plane.
    bool convex(label c) const { return convex_[c] != 0; }
    /// Faces of cell @p c: [begin,end) into cellFaces of view().
    label cellFacesBegin(label c) const { return mesh_.cellOffsets[c]; }
    /// End of the face list of cell @p c.
    label cellFacesEnd(label c) const { return mesh_.cellOffsets[c + 1]; }
    /// Face index of cell-face slot @p i.
    label cellFace(label i) const { return mesh_.cellFaces[i]; }
    /// +1 if the cell of slot @p i owns the face (normal outward), else -1.
    double cellFaceSign(label i) const { return cellFaceSign_[i]; }
    /// Face centre (OpenFOAM area-weighted) [m].
    const Vec3& faceCentre(label f) const { return faceCentre_[f]; }
    /// Unit face normal (out of the owner).
    const Vec3& faceNormal(label f) const { return faceNormal_[f]; }
    /// Unit in-plane tangent e1 of face f; e2 = normal x e1.
    const Vec3& faceTangent(label f) const { return faceTangent_[f]; }
    /// True if the face is planar to round-off (1e-12 relative).
    bool facePlanar(label f) const { return facePlanar_[f] != 0; }

    // ---- location --------------------------------------------------------
    /**
     * @brief Largest signed distance of @p x outside the faces (3D) / edges
     *        (2D, xy only) of cell @p c [m]; <= 0 means inside a convex cell.
     */
    double outsideDistance(label c, const Vec3& x) const;

    /// 2D only: outsideDistance() for the point (x, y), inline for hot loops.
    double outsideDistance2D(label c, double x, double y) const
    {
        const label b = polyOffsets_[c];
        const label e = polyOffsets_[c + 1];
        double worst = edgeNormal_[b][0] * x + edgeNormal_[b][1] * y - edgeOffset_[b];
        for (label k = b + 1; k < e; ++k)
        {
            const double d = edgeNormal_[k][0] * x + edgeNormal_[k][1] * y - edgeOffset_[k];
            worst = d > worst ? d : worst;
        }
        return worst;
    }

    /**
     * @brief Whether @p x lies in cell @p c (face-plane test, tolerance
     *        1e-9 x bounding radius; 2D uses xy only, non-convex 2D polygons
     *        use a winding-number test, non-convex 3D cells their tet
     *        decomposition).
     */
    bool contains(label c, const Vec3& x) const;

    /**
     * @brief Find the cell containing @p x.
     *
     * Starts from @p hint (e.g. the cell of the previous map) and walks
     * across the most violated face towards @p x (cost ~ cells crossed); if
     * that fails, searches the uniform bin grid. A point on a face belongs to
     * either cell. Points within 1e-6 x (cell bounding radius) outside the
     * mesh are attributed to the nearest boundary cell.
     * @return cell index, or -1 if @p x lies outside the mesh.
     */
    label findCell(const Vec3& x, label hint = -1) const;

    /// Axis-aligned bounding box of the mesh [m].
    const Vec3& boundsMin() const { return bbMin_; }
    /// Axis-aligned bounding box of the mesh [m].
    const Vec3& boundsMax() const { return bbMax_; }

private:
    void prepareFaces();
    void prepareAdjacency();
    void prepare2D();
    void prepare3D();
    void prepareBins();
    /// Recognise 3D cell @p c as a tet/prism/hex of the `overlap` library:
    /// fills shape_, shapeVerts_ and shapeVolume_; false for a polyhedron.
    bool classify3D(label c);
    /// classify3D() stage 1: shape and base size (3 or 4) from the face
    /// counts; false if a face is warped or the counts fit no model.
    bool candidateShape(label c, CellShape& s, int& nBase) const;
    /// classify3D() stage 2: the base face's vertices in v[0, nBase),
    /// oriented with their right-hand normal into the cell.
    void orientedBase(label c, int nBase, label* v) const;
    /// classify3D() stage 3 (tet): the vertex off the base in v[3].
    bool findTetApex(label c, label* v) const;
    /// classify3D() stage 3 (prism, hex): v[nBase + k], the vertex joined
    /// by an edge to base vertex k; false if not unique or missing.
    bool findTopVertices(label c, int nBase, label* v) const;
    /// classify3D() stage 4: every face of the cell is a face of the model.
    bool facesMatchModel(label c, CellShape s, const label* v) const;
    /// classify3D() stage 5: element volume from the `overlap` library;
    /// false if not positive (or a tet is inverted).
    bool elementVolume(CellShape s, const label* v, double& vol) const;
    /// Calls fn(F, p, q, sign) for every triangle (face centre F, face edge
    /// p-q) of the faces of cell @p c, sign = +1 where the face points out of
    /// c (-1 otherwise): with the cell centre, the cell's tet decomposition.
    /// Defined and used in CellMesh3D.cpp.
    template <class Fn>
    void forEachFaceTriangle(label c, Fn&& fn) const;
    /// Volume of the tet decomposition (cell centre, face centre, edge).
    double decompositionVolume(label c) const;
    /// True if all faces are planar and all vertices behind all face planes.
    bool convex3D(label c) const;
    /// 3D: whether @p x lies in one of the tets (cell centre, face centre,
    /// face edge) that decompose cell @p c (the decomposition of
    /// decompositionVolume(), OpenFOAM's cell tets), barycentric tolerance
    /// 1e-9: the exact test for non-convex cells and warped faces (the
    /// polyhedra of polyDualMesh), whose face planes cut off parts of the cell.
    bool containsByTets(label c, const Vec3& x) const;
    label walk(const Vec3& x, label start) const;
    label searchBins(const Vec3& x) const;
    double tol(label c) const { return 1e-9 * boundRadius_[c]; }

    MeshView mesh_;
    label nCells_ = 0;
    double depth_ = 0.0;

    std::vector<Vec3> faceCentre_, faceNormal_, faceTangent_;
    std::vector<std::uint8_t> facePlanar_;
    std::vector<double> cellFaceSign_;
    std::vector<label> adjOffsets_, adjCells_;
    std::vector<Vec3> boundCentre_;
    std::vector<double> boundRadius_;

    // 2D
    std::vector<label> polyOffsets_;
    std::vector<Vec2> polyVerts_;
    std::vector<Vec2> edgeNormal_;
    std::vector<double> edgeOffset_;
    std::vector<label> edgeNeighbour_;
    std::vector<double> polyArea_;
    std::vector<Vec2> polyCentroid_;

    // 3D
    std::vector<CellShape> shape_;
    std::vector<label> shapeVerts_;
    std::vector<double> shapeVolume_;
    std::vector<std::uint8_t> convex_;
    std::vector<label> boxIndex_; // per cell: index into boxLo_/boxHi_, or -1
    std::vector<Vec3> boxLo_, boxHi_;

    // bins
    Vec3 bbMin_ = Vec3::Zero(), bbMax_ = Vec3::Zero();
    Vec3 binSize_ = Vec3::Ones();
    std::array<label, 3> binDims_ = {{1, 1, 1}};
    std::vector<label> binOffsets_, binCells_;
};

} // namespace overlapMapping

#endif
