// yade-flex adapter: one SceneState per scene (GPL-2.0-or-later). What and why: FlexSceneState.hpp.
#include "FlexSceneState.hpp"

#include <memory>

namespace yade {
namespace flexa {
	namespace {
		// A state with the scene it belongs to: the scene's address and its interaction container's
		// owner (a scene loaded later at the same address has another container).
		struct Entry {
			const Scene*                          scene = nullptr;
			boost::weak_ptr<InteractionContainer> container;
			std::unique_ptr<SceneState>           state;
		};
		struct Registry {
			std::mutex         m;
			std::vector<Entry> entries;
		};
		// never destroyed: an engine may still ask during YADE's own teardown, and a thread's exit
		// would otherwise release weak references outside Python's lock, at no set time
		Registry& registry()
		{
			static Registry* r = new Registry;
			return *r;
		}
		struct LastAsked {
			const Scene*                          scene = nullptr;
			boost::weak_ptr<InteractionContainer> container;
			SceneState*                           state = nullptr;
		};
	} // namespace

	SceneState& sceneState(const Scene* scene)
	{
		thread_local LastAsked* last = new LastAsked; // (never destroyed, as the registry)
		if (last->scene == scene && sameOwner(last->container, scene->interactions)) return *last->state;
		Registry&                   r = registry();
		std::lock_guard<std::mutex> lock(r.m);
		SceneState*                 found = nullptr;
		for (const Entry& e : r.entries)
			if (e.scene == scene && sameOwner(e.container, scene->interactions)) found = e.state.get();
		if (!found) {
			// the states of released scenes go (a thread's LastAsked may still point at one: its
			// container's owner, kept by the weak reference, matches no live scene's, so it is never
			// read again)
			std::vector<Entry> kept;
			for (Entry& e : r.entries)
				if (!e.container.expired()) kept.push_back(std::move(e));
			r.entries.swap(kept);
			Entry e;
			e.scene     = scene;
			e.container = scene->interactions;
			e.state.reset(new SceneState);
			found = e.state.get();
			r.entries.push_back(std::move(e));
		}
		last->scene     = scene;
		last->container = scene->interactions;
		last->state     = found;
		return *found;
	}
} // namespace flexa
} // namespace yade
