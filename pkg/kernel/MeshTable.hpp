// A copy of what the ownership rule reads of a mesh (kernel/Ownership.hpp), taken once for a pass
// over the contacts in which nothing moves (GPL-2.0-or-later).
//
// Ownership asks the mesh for the same few nodes and elements many times per pass (every member
// of every cluster visits its neighbours); a scene's mesh answers each question by a chain of
// dependent loads through its bodies. The table holds, for the ids entered (the elements and
// their nodes), copies of the mesh's answers at refresh(): a node's position and the elements on
// it, an element's nodes and radius, in arrays read through a slot per id.
// TabledMesh reads the table where it has an entry and the mesh elsewhere, so its answers are
// the mesh's, bit for bit, as long as the table was refreshed since the mesh last changed: the
// ids entered decide only what is fast, never what is answered.
#pragma once
#include "Ownership.hpp"
#include "Types.hpp"

#include <vector>

namespace flex {

class MeshTable {
public:
	struct Node {
		Vec3 pos    = Vec3::Zero();
		bool hasPos = false;      // the mesh's pos() was not null
		int  first = 0, last = 0; // the mesh's elementsAt(), in onNodes_
	};

	/// No entries; ids from 0 to `ids` - 1 may be entered.
	void clear(long ids)
	{
		nodeSlot_.assign(ids > 0 ? ids : 0, -1);
		elementSlot_.assign(ids > 0 ? ids : 0, -1);
		nodeIds_.clear();
		elementIds_.clear();
		nodes_.clear();
		elements_.clear();
		onNodes_.clear();
	}
	/// Enter an id as a node / an element (ids outside [0, ids) and repeats are left out).
	void addNode(int id)
	{
		if (id < 0 || id >= (long)nodeSlot_.size() || nodeSlot_[id] >= 0) return;
		nodeSlot_[id] = (int)nodeIds_.size();
		nodeIds_.push_back(id);
		nodes_.emplace_back();
	}
	void addElement(int id)
	{
		if (id < 0 || id >= (long)elementSlot_.size() || elementSlot_[id] >= 0) return;
		elementSlot_[id] = (int)elementIds_.size();
		elementIds_.push_back(id);
		elements_.emplace_back();
	}
	/// Every entry asked of `mesh` again (the Mesh view of kernel/Ownership.hpp).
	template <class Mesh> void refresh(const Mesh& mesh)
	{
		onNodes_.clear();
		for (size_t k = 0; k < nodeIds_.size(); ++k) {
			Node&       n = nodes_[k];
			const Vec3* p = mesh.pos(nodeIds_[k]);
			n.hasPos      = p != nullptr;
			n.pos         = p ? *p : Vec3(Vec3::Zero());
			const auto on = mesh.elementsAt(nodeIds_[k]);
			n.first       = (int)onNodes_.size();
			onNodes_.insert(onNodes_.end(), on.begin(), on.end());
			n.last = (int)onNodes_.size();
		}
		for (size_t k = 0; k < elementIds_.size(); ++k)
			elements_[k] = mesh.element(elementIds_[k]);
	}
	/// The entry of node / element `id`; null: not entered.
	const Node* node(int id) const
	{
		if (id < 0 || id >= (long)nodeSlot_.size()) return nullptr;
		const int s = nodeSlot_[id];
		return s >= 0 ? &nodes_[s] : nullptr;
	}
	const ElementNodes* element(int id) const
	{
		if (id < 0 || id >= (long)elementSlot_.size()) return nullptr;
		const int s = elementSlot_[id];
		return s >= 0 ? &elements_[s] : nullptr;
	}
	/// The elements on node n (an entry of this table).
	IdRange elementsAt(const Node& n) const { return IdRange { onNodes_.data() + n.first, onNodes_.data() + n.last }; }
	long    nodes() const { return (long)nodeIds_.size(); }
	long elements() const { return (long)elementIds_.size(); }

private:
	std::vector<int>          nodeSlot_, elementSlot_; // by id: the entry's slot, -1 none
	std::vector<int>          nodeIds_, elementIds_;   // by slot: the id
	std::vector<Node>         nodes_;
	std::vector<ElementNodes> elements_;
	std::vector<int>          onNodes_; // the elements on each node, node after node
};

/// The Mesh view of kernel/Ownership.hpp: the table's entries where it has them (table null: none),
/// `mesh` elsewhere.
template <class Mesh> struct TabledMesh {
	const MeshTable* table;
	Mesh             mesh;
	const Vec3*      pos(int id) const
	{
		if (const MeshTable::Node* n = table ? table->node(id) : nullptr) return n->hasPos ? &n->pos : nullptr;
		return mesh.pos(id);
	}
	IdRange elementsAt(int id) const
	{
		if (const MeshTable::Node* n = table ? table->node(id) : nullptr) return table->elementsAt(*n);
		return mesh.elementsAt(id);
	}
	ElementNodes element(int id) const
	{
		if (const ElementNodes* e = table ? table->element(id) : nullptr) return *e;
		return mesh.element(id);
	}
};

} // namespace flex
