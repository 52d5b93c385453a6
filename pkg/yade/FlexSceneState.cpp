// yade-flex adapter: one SceneState per scene (GPL-2.0-or-later). What and why: FlexSceneState.hpp.
#include "FlexSceneState.hpp"

#include <memory>

namespace yade {
namespace flexa {
	std::atomic<const SceneEntry*> lastSceneEntry { nullptr };

	namespace {
		struct Registry {
			std::mutex                                                    m;
			std::vector<std::unique_ptr<SceneEntry>>                      entries; // never freed: lastSceneEntry may point at any
			std::vector<std::pair<SceneEntry*, std::unique_ptr<SceneState>>> live;    // the entries of scenes not released, with their states
		};
		// never destroyed: an engine may still ask during YADE's own teardown, and the weak
		// references would otherwise be released at no set time
		Registry& registry()
		{
			static Registry* r = new Registry;
			return *r;
		}
	} // namespace

	SceneState& sceneStateOf(const Scene* scene)
	{
		Registry&                   r = registry();
		std::lock_guard<std::mutex> lock(r.m);
		SceneEntry*                 found = nullptr;
		for (const auto& l : r.live)
			if (l.first->scene == scene && sameOwner(l.first->container, scene->interactions)) found = l.first;
		if (!found) {
			// the states of released scenes go; their entries stay (a reader may hold one: its
			// container's owner, kept by the weak reference, matches no live scene's, so its state
			// is never read)
			std::vector<std::pair<SceneEntry*, std::unique_ptr<SceneState>>> kept;
			for (auto& l : r.live)
				if (!l.first->container.expired()) kept.push_back(std::move(l));
			r.live.swap(kept);
			r.entries.emplace_back(new SceneEntry);
			found            = r.entries.back().get();
			found->scene     = scene;
			found->container = scene->interactions;
			r.live.emplace_back(found, std::unique_ptr<SceneState>(new SceneState));
			found->state = r.live.back().second.get();
		}
		lastSceneEntry.store(found, std::memory_order_release);
		return *found->state;
	}
} // namespace flexa
} // namespace yade
