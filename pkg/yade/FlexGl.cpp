// yade-flex adapter: Gl1 functors, drawing nodes, cylinders and facets in YADE's 3D view
// (GPL-2.0-or-later). See FlexGl.hpp.
#include "FlexGl.hpp"
#include "FlexElements.hpp"

#include <GL/gl.h>
#include <GL/glu.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace yade {

YADE_PLUGIN((Gl1_FlexNode)(Gl1_FlexCylinder)(Gl1_FlexFacet));

bool     Gl1_FlexNode::show;
int      Gl1_FlexNode::slices;
bool     Gl1_FlexCylinder::colorByForce;
Vector2r Gl1_FlexCylinder::forceRange;
Vector2r Gl1_FlexCylinder::lastRange;
bool     Gl1_FlexCylinder::caps;
int      Gl1_FlexCylinder::slices;
bool     Gl1_FlexFacet::colorByForce;
Vector2r Gl1_FlexFacet::forceRange;
Vector2r Gl1_FlexFacet::lastRange;

namespace {
	// One quadric for all views: it holds drawing options only, no GL object.
	GLUquadric* quadric()
	{
		static GLUquadric* q = [] {
			GLUquadric* p = gluNewQuadric();
			gluQuadricNormals(p, GLU_SMOOTH);
			gluQuadricOrientation(p, GLU_OUTSIDE);
			return p;
		}();
		return q;
	}

	void vertex(const Vector3r& p) { glVertex3d(p[0], p[1], p[2]); }
	void color(const Vector3r& c) { glColor3d(c[0], c[1], c[2]); }

	/// Position of a node in the frame the renderer set up for the element body (translated to
	/// its state->pos, rotated by its ori; see FlexGl.hpp).
	Vector3r local(const State& element, const Vector3r& x) { return element.ori.conjugate() * (x - element.pos); }

	/// Blue (value <= range[0]) - grey (midway) - red (value >= range[1]); grey for an empty range.
	Vector3r forceColor(Real value, const Vector2r& range)
	{
		const Vector3r blue(0.15, 0.35, 0.95), grey(0.75, 0.75, 0.75), red(0.95, 0.15, 0.10);
		if (!(range[1] > range[0]) || !std::isfinite(value)) return grey;
		const Real t = std::min<Real>(1, std::max<Real>(0, (value - range[0]) / (range[1] - range[0])));
		return t < 0.5 ? Vector3r(blue + 2 * t * (grey - blue)) : Vector3r(grey + (2 * t - 1) * (red - grey));
	}

	/// Id of the element body holding `shape`, found among the elements of its first node; -1 if
	/// not found.
	Body::id_t elementId(const Scene* scene, const Shape* shape, Body::id_t node)
	{
		if (node < 0 || node >= (Body::id_t)scene->bodies->size() || !(*scene->bodies)[node]) return -1;
		const FlexNode* n = dynamic_cast<const FlexNode*>((*scene->bodies)[node]->shape.get());
		if (!n) return -1;
		for (int e : n->elements)
			if (e >= 0 && e < (Body::id_t)scene->bodies->size() && (*scene->bodies)[e] && (*scene->bodies)[e]->shape.get() == shape) return e;
		return -1;
	}

	/// Automatic colour range, +- the largest |value| over all elements of one type, computed
	/// once per frame. The renderer draws bodies in increasing id order, so a frame starts when
	/// an element's id is not larger than the previous one's (or in another scene).
	struct FrameRange {
		const Scene* scene  = nullptr;
		Body::id_t   lastId = -1;
		Real         maxAbs = 0;
	};
	template <class ShapeT, class Value> Vector2r colorRange(FrameRange& fr, const Vector2r& userRange, const Scene* scene, Body::id_t id, Value value)
	{
		if (userRange[1] > userRange[0]) return userRange;
		if (id < 0) return Vector2r(-fr.maxAbs, fr.maxAbs); // not identified: keep the frame's range
		if (scene != fr.scene || id <= fr.lastId) {
			fr.scene  = scene;
			fr.maxAbs = 0;
			for (const auto& b : *scene->bodies)
				if (b)
					if (const ShapeT* s = dynamic_cast<const ShapeT*>(b->shape.get()))
						if (std::isfinite(value(*s))) fr.maxAbs = std::max<Real>(fr.maxAbs, std::abs(value(*s)));
		}
		fr.lastId = id;
		return Vector2r(-fr.maxAbs, fr.maxAbs);
	}

	/// Lines, unlit (lighting without normals shades lines arbitrarily).
	template <class Draw> void unlitLines(GLenum mode, Draw draw)
	{
		glPushAttrib(GL_ENABLE_BIT);
		glDisable(GL_LIGHTING);
		glBegin(mode);
		draw();
		glEnd();
		glPopAttrib();
	}

	void sphereAt(const Vector3r& p, Real radius, int slices)
	{
		glPushMatrix();
		glTranslated(p[0], p[1], p[2]);
		gluSphere(quadric(), radius, slices, std::max(2, slices / 2));
		glPopMatrix();
	}

	/// Tube of `radius` from a to b: gluCylinder runs along +z from the origin, so rotate z onto
	/// b - a about z x (b - a).
	void tube(const Vector3r& a, const Vector3r& b, Real radius, int slices)
	{
		const Vector3r d = b - a;
		const Real     L = d.norm();
		if (!(L > 0)) return;
		const Vector3r axis = Vector3r::UnitZ().cross(d);
		const Real     deg  = std::atan2(axis.norm(), d[2]) * 180 / M_PI;
		glPushMatrix();
		glTranslated(a[0], a[1], a[2]);
		if (axis.norm() > 1e-12 * L)
			glRotated(deg, axis[0], axis[1], axis[2]);
		else if (d[2] < 0)
			glRotated(180, 1, 0, 0);
		gluCylinder(quadric(), radius, radius, L, slices, 1);
		glPopMatrix();
	}
} // namespace

void Gl1_FlexNode::go(const shared_ptr<Shape>& sh, const shared_ptr<State>&, bool wire, const GLViewInfo&)
{
	if (!show) return;
	const FlexNode& n = static_cast<const FlexNode&>(*sh);
	if (!(n.radius > 0) || !std::isfinite(n.radius)) return;
	color(n.color);
	gluQuadricDrawStyle(quadric(), wire ? GLU_LINE : GLU_FILL);
	sphereAt(Vector3r::Zero(), n.radius, std::max(3, slices)); // the renderer already moved to the node
	gluQuadricDrawStyle(quadric(), GLU_FILL);
}

void Gl1_FlexCylinder::go(const shared_ptr<Shape>& sh, const shared_ptr<State>& st, bool wire, const GLViewInfo&)
{
	const FlexCylinder& c  = static_cast<const FlexCylinder&>(*sh);
	const State*        s1 = flexa::stateOf(scene, c.node1);
	const State*        s2 = flexa::stateOf(scene, c.node2);
	if (!s1 || !s2) return;
	const Vector3r a = local(*st, s1->pos), b = local(*st, s2->pos);
	if (colorByForce) {
		static FrameRange fr;
		lastRange = colorRange<FlexCylinder>(
		        fr, forceRange, scene, elementId(scene, sh.get(), c.node1), [](const FlexCylinder& e) { return e.axialForce; });
		color(forceColor(c.axialForce, lastRange));
	} else
		color(c.color);
	if (wire) {
		unlitLines(GL_LINES, [&] {
			vertex(a);
			vertex(b);
		});
		return;
	}
	const int n = std::max(3, slices);
	tube(a, b, c.radius, n);
	if (caps) {
		sphereAt(a, c.radius, n);
		sphereAt(b, c.radius, n);
	}
}

void Gl1_FlexFacet::go(const shared_ptr<Shape>& sh, const shared_ptr<State>& st, bool wire, const GLViewInfo&)
{
	const FlexFacet& f    = static_cast<const FlexFacet&>(*sh);
	const State*     s[3] = { flexa::stateOf(scene, f.node1), flexa::stateOf(scene, f.node2), flexa::stateOf(scene, f.node3) };
	if (!s[0] || !s[1] || !s[2]) return;
	const Vector3r x[3] = { local(*st, s[0]->pos), local(*st, s[1]->pos), local(*st, s[2]->pos) };
	Vector3r       col  = f.color;
	if (colorByForce) {
		static FrameRange fr;
		lastRange = colorRange<FlexFacet>(fr, forceRange, scene, elementId(scene, sh.get(), f.node1), [](const FlexFacet& e) { return e.n1; });
		col       = forceColor(f.n1, lastRange);
	}
	if (wire) {
		color(col);
		unlitLines(GL_LINE_LOOP, [&] {
			for (const Vector3r& p : x)
				vertex(p);
		});
		return;
	}
	// A membrane is seen from both sides: no culling, and the colour on back faces too (the
	// renderer sets two-sided lighting but tracks glColor on front faces only).
	const Vector3r n = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
	glPushAttrib(GL_ENABLE_BIT | GL_LIGHTING_BIT);
	glDisable(GL_CULL_FACE);
	glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
	color(col);
	glBegin(GL_TRIANGLES);
	glNormal3d(n[0], n[1], n[2]);
	for (const Vector3r& p : x)
		vertex(p);
	glEnd();
	glPopAttrib();
}

} // namespace yade
