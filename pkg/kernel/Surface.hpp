// A node of deformable elements against a rigid surface: a plane (YADE's Wall), a box, a
// triangle (YADE's Facet) (GPL-2.0-or-later).
//
// Why nodes: the elements are capsules (a segment and a radius r) and thick triangles (a
// triangle and a half-thickness r). Against a plane, the deepest point of a capsule or of a
// thick triangle is always one of its nodes (the distance to a plane is linear along the
// element, so its minimum is at a vertex; when it ties, every point of the tie is as deep as
// the nodes), so the contacts of a structure with a plane are exactly the contacts of its node
// spheres, one per node, with the largest radius of the elements on the node. Per element they
// would count a node once per element on it (a chain lying on a floor pushes twice at each
// node) and carry one point of a line contact. A box face or a facet's face is a plane in its
// region, so the same holds there. Between its nodes a cylinder meets a box or a triangle only at
// an edge or a vertex (segmentOnBoxEdges, segmentOnTriangleEdges): the distance from a convex
// body is convex along a segment, so a segment has at most one such point (or a stretch that ties
// with a node, which the node's contact carries).
//
// A surface made of several facets: a node over a shared edge or vertex touches each facet at
// the same point with the same overlap, and a node over one facet's face near its edge still
// touches the neighbour at that edge, more shallowly. As for elements (kernel/Ownership.hpp),
// two facet contacts of one node are LINKED when the closest point on either lies on what the two
// facets share (an edge or vertex, vertices equal within a relative 1e-9: the facets of a surface
// store their vertices apart); linked contacts, closed transitively, are one contact, carried by
// the deepest (ties, within 1e-9 of the longest edge: the lower id). At a shared edge both overlaps are equal, so a hand-over
// there neither creates nor destroys spring energy. A node in a valley touches both faces at
// distinct points: two contacts.
#pragma once
#include "Triangle.hpp"
#include "Types.hpp"

namespace flex {

/// A node sphere's centre x against a surface: the closest point on the surface, the unit
/// normal from the surface towards x, and the distance of x from the surface along that
/// normal (negative: x is behind the plane or inside the box). The overlap of a node of
/// contact radius r is r - distance.
struct SurfacePoint {
	Vec3     point    = Vec3::Zero();
	Vec3     normal   = Vec3::Zero();
	double   distance = 0;
	unsigned support  = 7; ///< a triangle: the vertices carrying the point (7: its face); else 7
};

/// The plane x[axis] = pos (YADE's Wall). sense: +1 (-1) only the positive (negative) side
/// pushes, 0 both; a two-sided plane pushes towards the side given by `side` (+1 or -1; 0: the
/// side x is on now, +1 on the plane): a contact keeps the side it started from, so a node
/// pushed through the plane is pushed back.
SurfacePoint nodeOnPlane(const Vec3& x, int axis, double pos, int sense, int side);

/// A box of half-sizes ext centred at the origin, x in the box's frame. Outside: the closest
/// point of the box. Inside: the closest point of the nearest face, distance negative.
SurfacePoint nodeOnBox(const Vec3& x, const Vec3& ext);

/// Distances within kNodeTie x the sizes involved count as equal: a facet edge contact is kept only
/// where it is nearer than both nodes by more (one found a round-off away from a node is the node's,
/// whose own contact carries it; the overlap changes by no more when the contact passes between
/// them). segmentOnBoxEdges compares exactly.
constexpr double kNodeTie = 1e-9;

/// The contact of an element's interior with a box edge: the segment (x0, x1) in the box's frame
/// (half-sizes ext). A box's face can meet a capsule's interior only where its deepest point is a
/// node (a plane: above); between its nodes an element meets the box at an edge (a wire draped
/// over a block, a small block on a coarse net). valid: the box's closest point to the
/// segment lies on an edge, at an interior point u of the segment (0 < u < 1), outside the box,
/// and nearer than both nodes (at u -> 0 or 1 the contact becomes the node's, at the same
/// distance). point: on the edge; normal: from the edge to the segment's point.
struct SegmentEdge {
	bool   valid = false;
	double u     = 0;
	Vec3   onSegment = Vec3::Zero(), point = Vec3::Zero(), normal = Vec3::Zero();
	double distance = 0;
	unsigned support = 7; ///< a triangle: its vertices carrying `point` (an edge's two, or one); a box: 7
};
SegmentEdge segmentOnBoxEdges(const Vec3& x0, const Vec3& x1, const Vec3& ext);

/// The triangle (a, b, c), of face normal nf = (b-a)x(c-a) normalized. In the face region the
/// normal is +-nf, towards `side` (+1: nf, -1: -nf; 0: the side x is on now, +1 on the plane),
/// distance signed as for a plane; in an edge or vertex region, from the closest point to x
/// (on the plane's side `side` when x lies on the triangle's boundary).
SurfacePoint nodeOnTriangle(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, int side);

/// The same for the triangle (a, b, c) (YADE's Facet): valid where the triangle's closest point to
/// the segment lies on an edge or vertex (not its face), at an interior point of the segment off
/// the triangle, nearer than both nodes. A wire over a ridge or the rim of a surface of facets.
/// support: the vertices carrying the point (for the ownership among facets, FacetHit).
SegmentEdge segmentOnTriangleEdges(const Vec3& x0, const Vec3& x1, const Vec3& a, const Vec3& b, const Vec3& c);

/// The contact of a membrane's interior (a thick triangle, midplane (x0, x1, x2)) with a rigid
/// surface's edge or vertex (a box corner or edge, a facet's rim or ridge pressed into a sheet).
/// The distance from a convex body is convex over the triangle, so its minimum is one point (or a
/// stretch that ties with it): at a node (the node's contact), or, between the nodes, where the
/// body's closest point is an edge or vertex (over a box face or a facet's face the distance is
/// that of a plane, linear over the triangle: a node is as deep). valid: the surface's closest
/// point to the membrane's point lies on an edge or vertex, nearer than the three nodes. pierced:
/// an edge passes through the midplane (the overlap is the half-thickness wherever it goes, see
/// kernel/Onset.hpp); point and onTriangle are then the piercing point, distance 0.
struct TriangleEdge {
	bool     valid = false, pierced = false;
	double   w[3]  = { 0, 0, 0 }; ///< barycentric weights of onTriangle on the membrane
	unsigned triSupport = 7;      ///< the membrane's nodes carrying onTriangle
	Vec3     onTriangle = Vec3::Zero(), point = Vec3::Zero(), normal = Vec3::Zero();
	double   distance = 0;
	unsigned support  = 7; ///< a rigid triangle: its vertices carrying `point`; a box: 7
};
/// Conservative separation tests of a membrane (x0, x1, x2) from a surface (see
/// segmentTriangleApart): true only if no point of it comes within reach of the surface: all three
/// nodes beyond one face plane of the box (in its frame, half-sizes ext), or beyond reach on one
/// side of the triangle (a, b, c)'s plane. False says nothing.
bool membraneApartFromBox(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& ext, double reach);
bool membraneApartFromTriangle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& a, const Vec3& b, const Vec3& c, double reach);
/// The box of half-sizes ext at the origin against the membrane (x0, x1, x2) in the box's frame.
TriangleEdge boxEdgesOnTriangle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& ext);
/// The rigid triangle (a, b, c) (YADE's Facet) against the membrane (x0, x1, x2).
TriangleEdge triangleEdgesOnTriangle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& a, const Vec3& b, const Vec3& c);

struct FacetHit;
/// A segment's interior against a surface of facets: for facet k (vertices tri[k], body id ids[k])
/// its segmentOnTriangleEdges in edge[k] and, for ownsFacetCluster, hit[k] with the overlap
/// r - distance, set to -1 where there is none or where another of the facets is nearer to the
/// segment's point than this edge (a point over a neighbour's face, or a coplanar neighbour's
/// shared edge, is that face's, and the nodes carry it). n <= 64.
void segmentOnFacets(const Vec3& x0, const Vec3& x1, double r, const Vec3 (*tri)[3], const int* ids, int n, SegmentEdge* edge, FacetHit* hit);

/// A membrane triangle (x0, x1, x2), half-thickness r, against a surface of facets, as
/// segmentOnFacets: edge[k] its triangleEdgesOnTriangle with facet k, hit[k] for ownsFacetCluster
/// (-1 where there is none or another facet is nearer to the membrane's point). n <= 64.
void membraneOnFacets(const Vec3& x0, const Vec3& x1, const Vec3& x2, double r, const Vec3 (*tri)[3], const int* ids, int n, TriangleEdge* edge, FacetHit* hit);

/// One facet contact of a node (or of a cylinder's interior, segmentOnFacets), for the ownership among the node's facet contacts.
struct FacetHit {
	int      id = -1;  ///< the facet's body id
	double   overlap;  ///< r - distance
	Vec3     v[3];     ///< the facet's vertices
	unsigned support;  ///< SurfacePoint::support
};
/// Whether the closest point of contact a lies on what facets a and b share: every vertex of
/// a's support coincides with a vertex of b (within 1e-9 of the longer edge of the two).
bool onSharedFeature(const FacetHit& a, const FacetHit& b);
/// Whether hit[self] carries its cluster's contact among the node's facet contacts hit[0..n)
/// (those with overlap > 0 take part; see the top of this file; n <= 64). If so, the other members of
/// the cluster are in beaten (ids, at most 8 kept).
bool ownsFacetCluster(const FacetHit* hit, int n, int self, int* beaten, int& nBeaten);

/// A rigid union of bodies (a clump of boxes) meets a probe (a node's centre, a wire's or a
/// membrane's nearest point) once per point of its outer surface. Its members' surfaces also run
/// where members touch: a member's edge on a seam lies inside the union's face (or inside the
/// union), and a wire under the seam of two boxes side by side touches both members' edges at
/// one point. So member `self`'s contact, at `point` at `distance` from the probe, on an edge or
/// vertex of the member (onRim) or on its face, is the union's unless
///  - another member reaches the probe at the same point (within tol) as near: one contact, the
///    lower id's;
///  - it is on an edge or vertex and another member reaches the probe as near or nearer at another
///    point: the union's surface nearest the probe is that member's (a face contact is never
///    dropped so: a node in the valley of an L-shaped clump touches both faces, two contacts).
struct MemberPoint {
	int    id       = -1;
	double distance = 0;
	Vec3   point    = Vec3::Zero();
	bool   onRim    = false; ///< on an edge or vertex of the member (not its face)
};
/// Whether self carries its contact among the members others[0..n); if so, the members at the
/// same point are in beaten (ids, at most 8).
bool ownsOnUnion(const MemberPoint& self, const MemberPoint* others, int n, double tol, int* beaten, int& nBeaten);
/// Whether the box point p (in the box's frame, on its surface) lies on an edge or vertex: two or
/// three coordinates on the box's extent ext (within tol).
bool onBoxRim(const Vec3& p, const Vec3& ext, double tol);

} // namespace flex
