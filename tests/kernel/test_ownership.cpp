// yade-flex kernel tests: which element carries a contact (kernel/Ownership.hpp), on small meshes
// of exact geometry where the number of distinct contacts is known (GPL-2.0-or-later).
#include "kernel/MeshTable.hpp"
#include "kernel/Ownership.hpp"
#include "test_util.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>
#include <vector>

using namespace flex;

namespace {
// A mesh as the kernel reads it: nodes 0..n-1, elements with ids from kFirstElement on (ids of
// the same space as the nodes', as YADE's bodies: a node id is not an element).
constexpr int kFirstElement = 100;
struct TestMesh {
	std::vector<Vec3>             x;
	std::vector<ElementNodes>     el;
	std::vector<std::vector<int>> at;
	int                           node(double px, double py, double pz)
	{
		x.emplace_back(px, py, pz);
		at.emplace_back();
		return (int)x.size() - 1;
	}
	int add(std::initializer_list<int> nodes, double radius)
	{
		ElementNodes e;
		for (int n : nodes)
			e.nodes[e.nNodes++] = n;
		e.radius = radius;
		el.push_back(e);
		const int id = kFirstElement + (int)el.size() - 1;
		for (int n : nodes)
			at[n].push_back(id);
		return id;
	}
	const Vec3*             pos(int n) const { return n >= 0 && n < (int)x.size() ? &x[n] : nullptr; }
	IdRange                 elementsAt(int n) const { return idRange(n >= 0 && n < (int)at.size() ? &at[n] : nullptr); }
	ElementNodes            element(int id) const
	{
		const int k = id - kFirstElement;
		return k >= 0 && k < (int)el.size() ? el[k] : ElementNodes();
	}
};

// The elements that carry a contact with the probe sphere (P, R), each with the cluster members
// it beat: every element that overlaps asks, as its contact functor does.
// (Mesh: TestMesh or a view of it)
template <class Mesh> std::map<int, std::set<int>> owners(const TestMesh& t, const Mesh& m, const Vec3& P, double R)
{
	std::map<int, std::set<int>> out;
	for (size_t k = 0; k < t.el.size(); ++k) {
		const int          id  = kFirstElement + (int)k;
		const ElementNodes e   = m.element(id);
		const Hit          hit = probe(m, e, P, R);
		if (!(hit.overlap > 0)) continue;
		int beaten[8], nb = 0;
		if (owns(m, e, id, P, R, hit, beaten, nb)) out[id] = std::set<int>(beaten, beaten + nb);
	}
	return out;
}
std::map<int, std::set<int>> owners(const TestMesh& m, const Vec3& P, double R) { return owners(m, m, P, R); }
// The element pairs (a, b), a in `as`, b in `bs`, that carry a contact, each with the pairs it beat.
// screen: ownsPair's (false: every pair met evaluated). Mesh: TestMesh or a view of it.
template <class Mesh>
std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> pairOwnersInOrder(
        const Mesh& m, const std::vector<int>& as, const std::vector<int>& bs, bool screen = true)
{
	std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> out;
	for (int a : as)
		for (int b : bs) {
			std::pair<int, int> beaten[8];
			int                 nb = 0;
			if (ownsPair(m, a, m.element(a), b, m.element(b), beaten, nb, screen))
				out[{ a, b }] = std::vector<std::pair<int, int>>(beaten, beaten + nb);
		}
	return out;
}
std::map<std::pair<int, int>, std::set<std::pair<int, int>>> pairOwners(const TestMesh& m, const std::vector<int>& as, const std::vector<int>& bs)
{
	std::map<std::pair<int, int>, std::set<std::pair<int, int>>> out;
	for (const auto& [pq, beaten] : pairOwnersInOrder(m, as, bs)) {
		out[pq] = std::set<std::pair<int, int>>(beaten.begin(), beaten.end());
		EXPECT_EQ(pairOwnersInOrder(m, as, bs, false).at(pq), beaten); // (the screen changes nothing)
	}
	return out;
}
} // namespace

// A sphere resting on the shared node of a straight chain touches both links at that node: one
// contact, carried by the lower id (the overlaps are equal to the bit: the closest point is the
// node itself on both).
TEST(Ownership, SphereOnTheSharedNodeOfAChainIsOneContact)
{
	TestMesh   m;
	const int  n0 = m.node(0, 0, 0), n1 = m.node(1, 0, 0), n2 = m.node(2, 0, 0);
	const int  s0 = m.add({ n0, n1 }, 0.01), s1 = m.add({ n1, n2 }, 0.01);
	const Vec3 P(1, 0, 0.05);
	const Hit  h0 = probe(m, m.element(s0), P, 0.045), h1 = probe(m, m.element(s1), P, 0.045);
	EXPECT_EQ(h0.overlap, h1.overlap);
	EXPECT_NEAR(h0.overlap, 0.005, 1e-15);
	const auto o = owners(m, P, 0.045);
	ASSERT_EQ(o.size(), 1u);
	EXPECT_EQ(o.begin()->first, s0);
	EXPECT_EQ(o.begin()->second, std::set<int>({ s1 }));
}

// A sphere sitting in a square cell of four wires touches each at its middle, with normals 88
// degrees apart: four distinct contacts (merging them would push with one instead of four).
TEST(Ownership, SphereInANetCellTouchesFourWires)
{
	TestMesh  m;
	const int a = m.node(0, 0, 0), b = m.node(1, 0, 0), c = m.node(1, 1, 0), d = m.node(0, 1, 0);
	m.add({ a, b }, 0.01);
	m.add({ b, c }, 0.01);
	m.add({ c, d }, 0.01);
	m.add({ d, a }, 0.01);
	const double h = 0.1, R = std::sqrt(0.25 + h * h) - 0.01 + 0.005; // overlap 5 mm on each wire
	const auto   o = owners(m, Vec3(0.5, 0.5, h), R);
	EXPECT_EQ(o.size(), 4u);
	for (const auto& kv : o)
		EXPECT_TRUE(kv.second.empty());
}

// A large sphere on a nearly straight chain of three links touches all three; neighbours' normals
// are within 15 degrees, the outer links share no node and are linked only through the middle
// one. One contact, carried by the deepest link, which reports both others as beaten (the
// cluster is closed transitively, not decided between neighbours only).
TEST(Ownership, ShallowChainIsOneClusterClosedTransitively)
{
	TestMesh     m;
	const int    n0 = m.node(0, 0, 0.02), n1 = m.node(1, 0, 0), n2 = m.node(2, 0, 0.03), n3 = m.node(3, 0, 0.09);
	const int    s0 = m.add({ n0, n1 }, 0.01), s1 = m.add({ n1, n2 }, 0.01), s2 = m.add({ n2, n3 }, 0.01);
	const Vec3   P(0.5, 0, 5);
	const double R = 5.2; // reaches every link, the far one barely
	double       ov[3];
	for (int k = 0; k < 3; ++k)
		ov[k] = probe(m, m.element(s0 + k), P, R).overlap;
	ASSERT_GT(ov[2], 0);
	ASSERT_GT(ov[0], ov[1]); // deepest under the sphere, the far link only through the middle one
	ASSERT_GT(ov[1], ov[2]);
	const int  deepest = s0;
	const auto o       = owners(m, P, R);
	ASSERT_EQ(o.size(), 1u);
	EXPECT_EQ(o.begin()->first, deepest);
	std::set<int> others { s0, s1, s2 };
	others.erase(deepest);
	EXPECT_EQ(o.begin()->second, others);
}

// A sphere over the outside of a bend touches the first link at its end cap (the shared node)
// and the second link on its side, with normals 27 degrees apart: one contact patch at the
// bend, linked through the node the two share (not by the normals).
TEST(Ownership, SphereOverAConvexBendIsOneContact)
{
	TestMesh     m;
	const int    n0 = m.node(-1, 0, 0), n1 = m.node(0, 0, 0), n2 = m.node(1, 0, -1);
	const int    a = m.add({ n0, n1 }, 0.01), b = m.add({ n1, n2 }, 0.01);
	const Vec3   P(0.3, 0, 0.1);
	const double R  = 0.31;
	const Hit    ha = probe(m, m.element(a), P, R), hb = probe(m, m.element(b), P, R);
	ASSERT_GT(ha.overlap, 0);
	ASSERT_GT(hb.overlap, ha.overlap);
	ASSERT_EQ(ha.nSupport, 1); // a's closest point: the node
	EXPECT_LT((P - ha.point).normalized().dot((P - hb.point).normalized()), kMergeCos);
	const auto o = owners(m, P, R);
	ASSERT_EQ(o.size(), 1u);
	EXPECT_EQ(o.begin()->first, b);
}

// A sphere in a sharp kink (90 degrees) touches both legs away from the shared node: two
// contacts.
TEST(Ownership, SphereInASharpKinkTouchesBothLegs)
{
	TestMesh  m;
	const int n0 = m.node(-1, 0, 1), n1 = m.node(0, 0, 0), n2 = m.node(1, 0, 1);
	m.add({ n0, n1 }, 0.01);
	m.add({ n1, n2 }, 0.01);
	// centre on the bisector, 0.3 above the kink: 0.3 / sqrt(2) = 0.2121 from each leg, at points
	// away from the node
	const auto o = owners(m, Vec3(0, 0, 0.3), 0.3 / std::sqrt(2.0) - 0.01 + 0.002);
	EXPECT_EQ(o.size(), 2u);
}

// A bar across the ridge of a convex fold of two facets touches both at the ridge (their shared
// edge): one contact, carried by one of the two pairs (a probe-based rule let both push).
TEST(Ownership, BarOnAConvexFoldIsOneContact)
{
	TestMesh  m;
	const int e0 = m.node(0, -1, 0), e1 = m.node(0, 1, 0), left = m.node(-1, 0, -0.3), right = m.node(1, 0, -0.3);
	const int f1 = m.add({ e0, e1, left }, 0.002), f2 = m.add({ e0, e1, right }, 0.002);
	const int b0 = m.node(-0.5, 0.1, 0.01), b1 = m.node(0.5, 0.1, 0.01);
	const int bar = m.add({ b0, b1 }, 0.01);
	EXPECT_GT(pairHit(m, bar, m.element(bar), f1, m.element(f1)).overlap, 0);
	EXPECT_GT(pairHit(m, bar, m.element(bar), f2, m.element(f2)).overlap, 0);
	const auto o = pairOwners(m, { bar }, { f1, f2 });
	ASSERT_EQ(o.size(), 1u);
	EXPECT_EQ(o.begin()->second.size(), 1u); // the other pair, beaten
}

// A bar lying flat on a membrane strip of two facets touches each facet along a stretch, at
// closest points 1.5 m apart on the bar: two contacts (the parallel normals alone do not merge
// them: distinct contacts lose their force when merged).
TEST(Ownership, BarLyingAlongAMembraneTouchesEachFacet)
{
	TestMesh      m;
	const int     n0 = m.node(0, -1, 0), n1 = m.node(4, -1, 0), n2 = m.node(0, 1, 0), n3 = m.node(4, 1, 0);
	const int     f1 = m.add({ n0, n1, n2 }, 0.002), f2 = m.add({ n1, n3, n2 }, 0.002);
	const int     b0 = m.node(0.5, 0, 0.011), b1 = m.node(3.5, 0, 0.011);
	const int     bar = m.add({ b0, b1 }, 0.01);
	const PairHit h1 = pairHit(m, bar, m.element(bar), f1, m.element(f1)), h2 = pairHit(m, bar, m.element(bar), f2, m.element(f2));
	ASSERT_GT(h1.overlap, 0);
	ASSERT_GT(h2.overlap, 0);
	EXPECT_GT((h1.hx.point - h2.hx.point).norm(), 1.0);
	const auto o = pairOwners(m, { bar }, { f1, f2 });
	EXPECT_EQ(o.size(), 2u);
}

// A wire's node above the seam of two facets: (wire 1, facet 2) and (wire 2, facet 1) touch at
// the same point, the node over the shared edge, from different elements on both sides: one
// contact between them.
TEST(Ownership, WireNodeAboveASeamIsOneContact)
{
	TestMesh  m;
	const int e0 = m.node(0, -1, 0), e1 = m.node(0, 1, 0), l = m.node(-1, 0, 0), r = m.node(1, 0, 0);
	const int f1 = m.add({ e0, e1, l }, 0.002), f2 = m.add({ e0, e1, r }, 0.002);
	// the wire bends down at its node over the seam: each leg touches only at that node
	const int     w0 = m.node(-1, 0, 0.2), wn = m.node(0, 0, 0.011), w2 = m.node(1, 0, 0.2);
	const int     wire1 = m.add({ w0, wn }, 0.01), wire2 = m.add({ wn, w2 }, 0.01);
	const PairHit a = pairHit(m, wire1, m.element(wire1), f2, m.element(f2)), b = pairHit(m, wire2, m.element(wire2), f1, m.element(f1));
	ASSERT_GT(a.overlap, 0);
	ASSERT_GT(b.overlap, 0);
	EXPECT_LT((a.hx.point - b.hx.point).norm(), 1e-12); // the same point: the node
	const auto o = pairOwners(m, { wire1, wire2 }, { f1, f2 });
	ASSERT_EQ(o.size(), 1u); // all four pairs touch at the node: one contact
	EXPECT_EQ(o.begin()->second.size(), 3u);
}

// A node id is not an element: no element, no contact.
TEST(Ownership, NodesAreNotElements)
{
	TestMesh  m;
	const int n0 = m.node(0, 0, 0), n1 = m.node(1, 0, 0);
	const int s0 = m.add({ n0, n1 }, 0.01);
	EXPECT_EQ(m.element(n0).nNodes, 0);
	EXPECT_EQ(pairHit(m, s0, m.element(s0), n1, m.element(n1)).overlap, -std::numeric_limits<double>::infinity());
	EXPECT_EQ(probe(m, m.element(n1), Vec3(1, 0, 0), 1.0).overlap, -std::numeric_limits<double>::infinity());
}

// A wire net pressed into a crumpled membrane (wires over seams, net nodes over the membrane's
// vertices and edges, clusters of several pairs), and two nets crossing each other: ownsPair
// answers the same, owners and the pairs each beat in order, whether it screens the pairs it meets
// or evaluates them all.
namespace {
// A wire net pressed into a crumpled membrane (facets) and a second net lying across it, nodes
// jittered by `seed`: clusters of several element pairs of every kind.
struct CrumpledScene {
	TestMesh         m;
	std::vector<int> facets, wires, wires2;
	explicit CrumpledScene(unsigned seed)
	{
		const int N = 7;
		test::Rng rng(seed);
		int       mem[N + 1][N + 1], net[N + 1][N + 1], net2[N + 1][N + 1];
		for (int i = 0; i <= N; ++i)
			for (int j = 0; j <= N; ++j)
				mem[i][j] = m.node(0.1 * i, 0.1 * j, 0.004 * rng.uniform(-0.5, 0.5));
		for (int i = 0; i < N; ++i)
			for (int j = 0; j < N; ++j) {
				facets.push_back(m.add({ mem[i][j], mem[i + 1][j], mem[i + 1][j + 1] }, 0.002));
				facets.push_back(m.add({ mem[i][j], mem[i + 1][j + 1], mem[i][j + 1] }, 0.002));
			}
		// a net of 0.1 m cells over the membrane's nodes, sagging into it (radius 4 mm), and a
		// second net of 0.1 m cells turned 45 degrees, lying on the first
		for (int i = 0; i <= N; ++i)
			for (int j = 0; j <= N; ++j) {
				net[i][j]  = m.node(0.1 * i + 0.01 * rng.uniform(-0.5, 0.5), 0.1 * j + 0.01 * rng.uniform(-0.5, 0.5),
				         0.004 + 0.003 * rng.uniform(-0.5, 0.5));
				net2[i][j] = m.node(
				        0.35 + 0.0707 * (i - j), 0.0707 * (i + j) + 0.003 * rng.uniform(-0.5, 0.5), 0.0115 + 0.003 * rng.uniform(-0.5, 0.5));
			}
		for (int i = 0; i <= N; ++i)
			for (int j = 0; j <= N; ++j) {
				if (i < N) wires.push_back(m.add({ net[i][j], net[i + 1][j] }, 0.004));
				if (j < N) wires.push_back(m.add({ net[i][j], net[i][j + 1] }, 0.004));
				if (i < N) wires2.push_back(m.add({ net2[i][j], net2[i + 1][j] }, 0.004));
				if (j < N) wires2.push_back(m.add({ net2[i][j], net2[i][j + 1] }, 0.004));
			}
	}
};
} // namespace

TEST(Ownership, ScreeningThePairsMetChangesNoAnswer)
{
	for (unsigned seed : { 11u, 12u, 13u }) {
		const CrumpledScene     sc(seed);
		const TestMesh&         m          = sc.m;
		const std::vector<int>& facets     = sc.facets;
		const std::vector<int>& wires      = sc.wires;
		const std::vector<int>& wires2     = sc.wires2;
		const auto onMembrane = pairOwnersInOrder(m, wires, facets);
		long       beat       = 0;
		for (const auto& [pq, beaten] : onMembrane)
			beat += (long)beaten.size();
		EXPECT_GT(onMembrane.size(), 50u);
		EXPECT_GT(beat, 50); // (clusters of several pairs)
		EXPECT_EQ(onMembrane, pairOwnersInOrder(m, wires, facets, false));
		const auto crossing = pairOwnersInOrder(m, wires2, wires);
		EXPECT_GT(crossing.size(), 10u);
		EXPECT_EQ(crossing, pairOwnersInOrder(m, wires2, wires, false));
		EXPECT_EQ(pairOwnersInOrder(m, wires2, facets), pairOwnersInOrder(m, wires2, facets, false));
	}
}

// A table of the mesh (kernel/MeshTable.hpp) answers as the mesh: the same owners and beaten
// pairs, in order, whether it holds every element and node, some of them (the others read from
// the mesh) or none; after the mesh moved, a refreshed table answers as the moved mesh.
TEST(Ownership, ATableOfTheMeshGivesTheSameOwners)
{
	for (unsigned seed : { 21u, 22u }) {
		CrumpledScene sc(seed);
		TestMesh&     m   = sc.m;
		const long    ids = std::max((long)m.x.size(), kFirstElement + (long)m.el.size()); // (TestMesh: node and element ids may coincide)
		MeshTable     all, some, none;
		all.clear(ids);
		some.clear(ids);
		none.clear(ids);
		for (size_t k = 0; k < m.el.size(); ++k) {
			const int id = kFirstElement + (int)k;
			all.addElement(id);
			if (k % 3) some.addElement(id);
			for (int i = 0; i < m.el[k].nNodes; ++i) {
				all.addNode(m.el[k].nodes[i]);
				if (m.el[k].nodes[i] % 2) some.addNode(m.el[k].nodes[i]);
			}
		}
		all.addNode(-1);          // (left out: outside the ids)
		all.addElement((int)ids); // (the same)
		EXPECT_EQ(all.nodes(), (long)m.x.size());
		EXPECT_EQ(all.elements(), (long)m.el.size());
		for (int pass = 0; pass < 2; ++pass) {
			all.refresh(m);
			some.refresh(m);
			const TabledMesh<const TestMesh&> viaAll { &all, m }, viaSome { &some, m }, viaNone { &none, m }, noTable { nullptr, m };
			for (int id = -1; id <= ids; ++id) { // every answer of the full table is the mesh's
				const Vec3* p = viaAll.pos(id);
				ASSERT_EQ(p == nullptr, m.pos(id) == nullptr) << id;
				if (p) {
					EXPECT_NE(p, m.pos(id)) << id; // (read from the table for an entered node)
					EXPECT_EQ(*p, *m.pos(id)) << id;
				}
				const IdRange on = viaAll.elementsAt(id), ref = m.elementsAt(id);
				EXPECT_EQ(std::vector<int>(on.begin(), on.end()), std::vector<int>(ref.begin(), ref.end())) << id;
				if (!ref.empty()) EXPECT_NE(on.begin(), ref.begin()) << id; // (read from the table for an entered node)
				const ElementNodes a = viaAll.element(id), b = m.element(id);
				EXPECT_EQ(a.nNodes, b.nNodes) << id;
				EXPECT_EQ(a.radius, b.radius) << id;
				for (int i = 0; i < 3; ++i)
					EXPECT_EQ(a.nodes[i], b.nodes[i]) << id;
			}
			for (const auto& [as, bs] : { std::make_pair(sc.wires, sc.facets), std::make_pair(sc.wires2, sc.wires) }) {
				const auto ref = pairOwnersInOrder(m, as, bs);
				EXPECT_GT(ref.size(), 10u);
				EXPECT_EQ(pairOwnersInOrder(viaAll, as, bs), ref);
				EXPECT_EQ(pairOwnersInOrder(viaSome, as, bs), ref);
				EXPECT_EQ(pairOwnersInOrder(viaNone, as, bs), ref);
				EXPECT_EQ(pairOwnersInOrder(noTable, as, bs), ref);
			}
			// a grain pressed on a node of the upper net (its four wires: one cluster)
			const Vec3 P(0.35 + 0.0707, 0.2121, 0.04);
			const auto ref = owners(m, P, 0.03);
			ASSERT_EQ(ref.size(), 1u);
			EXPECT_FALSE(ref.begin()->second.empty());
			EXPECT_EQ(owners(m, viaAll, P, 0.03), ref);
			EXPECT_EQ(owners(m, viaSome, P, 0.03), ref);
			// the mesh moves (the nets pressed 2 mm deeper); the tables are refreshed at the next pass
			for (size_t n = 64; n < m.x.size(); ++n)
				m.x[n].z() -= 0.002;
		}
	}
}

// A contact functor hands ownsPair the hit it computed itself (segmentsPairHit,
// segmentTrianglePairHit from its own closest points): the same hit as pairHit's, bit for bit,
// and the same owners and beaten pairs in order.
TEST(Ownership, TheFunctorsOwnHitIsPairHits)
{
	auto same = [](const Hit& a, const Hit& b) {
		EXPECT_EQ(a.overlap, b.overlap);
		EXPECT_EQ(a.point, b.point);
		EXPECT_EQ(a.nSupport, b.nSupport);
		for (int k = 0; k < 3; ++k)
			EXPECT_EQ(a.support[k], b.support[k]);
	};
	for (unsigned seed : { 31u, 32u }) {
		const CrumpledScene sc(seed);
		const TestMesh&     m        = sc.m;
		long                touching = 0, owned = 0;
		for (const auto& [as, bs] : { std::make_pair(sc.wires, sc.facets), std::make_pair(sc.wires2, sc.wires), std::make_pair(sc.wires, sc.wires2) })
			for (int a : as)
				for (int b : bs) {
					const ElementNodes A = m.element(a), B = m.element(b);
					if (shareNode(A, B)) continue;
					const double reach = A.radius + B.radius;
					const Vec3 & x0 = *m.pos(A.nodes[0]), &x1 = *m.pos(A.nodes[1]), &y0 = *m.pos(B.nodes[0]), &y1 = *m.pos(B.nodes[1]);
					PairHit      given;
					if (B.isTriangle()) {
						const Vec3& y2 = *m.pos(B.nodes[2]);
						if (!segmentTriangleApart(x0, x1, y0, y1, y2, reach))
							given = segmentTrianglePairHit(A, B, closestPointsSegmentTriangle(x0, x1, y0, y1, y2), false);
					} else if (a < b) { // (two segments: the lower id first, as pairHit)
						if (!segmentsApart(x0, x1, y0, y1, reach))
							given = segmentsPairHit(A, B, closestPointsSegments(x0, x1, y0, y1), false);
					} else if (!segmentsApart(y0, y1, x0, x1, reach))
						given = segmentsPairHit(B, A, closestPointsSegments(y0, y1, x0, x1), true);
					const PairHit ref = pairHit(m, a, A, b, B);
					EXPECT_EQ(given.overlap, ref.overlap);
					EXPECT_EQ(given.n, ref.n);
					same(given.hx, ref.hx);
					same(given.hy, ref.hy);
					if (!(ref.overlap > 0)) continue;
					++touching;
					std::pair<int, int> beaten[8], beaten2[8];
					int                 nb = 0, nb2 = 0;
					const bool          own = ownsPair(m, a, A, b, B, beaten, nb);
					EXPECT_EQ(ownsPair(m, a, A, b, B, beaten2, nb2, true, &given), own);
					owned += own;
					if (!own) continue;
					ASSERT_EQ(nb2, nb);
					for (int k = 0; k < nb; ++k)
						EXPECT_EQ(beaten2[k], beaten[k]);
				}
		EXPECT_GT(touching, 100);
		EXPECT_GT(owned, 50);
		EXPECT_LT(owned, touching); // (clusters of several pairs)
	}
}
