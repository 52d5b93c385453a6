// Precompiled header of the YADE adapter: the heavy YADE includes, parsed once.
#pragma once
#include <core/Body.hpp>
#include <core/Dispatching.hpp>
#include <core/GlobalEngine.hpp>
#include <core/Interaction.hpp>
#include <core/Omega.hpp>
#include <core/Scene.hpp>
#include <core/Shape.hpp>
#include <core/State.hpp>
#include <core/Aabb.hpp>
#include <pkg/common/Sphere.hpp>
#include <pkg/dem/DemXDofGeom.hpp>
#include <pkg/dem/FrictPhys.hpp>
#include <pkg/dem/NewtonIntegrator.hpp>
