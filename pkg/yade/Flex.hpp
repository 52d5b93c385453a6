// yade-flex adapter: the YADE classes of deformable elements, one header each (GPL-2.0-or-later).
//
//  - FlexNode.hpp             FlexNode: a node carrying mass, inertia and all DOFs
//  - FlexMat.hpp              FlexMat: material (FrictMat + beam/bond/wire parameters)
//  - FlexCylinder.hpp         FlexCylinder: capsule between two nodes, bond and contact surface;
//                             Bo1_FlexCylinder_Aabb
//  - FlexContactGeom.hpp      FlexContactGeom, and the ownership rule (one contact where
//                             elements meet)
//  - FlexContactFunctors.hpp  sphere-cylinder, cylinder-cylinder, sphere-sphere geometry
//  - FlexContactLaw.hpp       Law2_FlexContactGeom_FrictPhys_CundallStrack
//  - FlexElementEngine.hpp    internal forces of all bonds and membranes; rupture
//  - FlexTimeStepper.hpp      critical time step from bonds and contacts
//  - FlexNewtonIntegrator.hpp the integrator of the nodes and grains
// Membranes: FlexFacet.hpp; YADE's rigid surfaces: FlexSurfaces.hpp.
#pragma once
#include "FlexContactFunctors.hpp"
#include "FlexContactGeom.hpp"
#include "FlexContactLaw.hpp"
#include "FlexCylinder.hpp"
#include "FlexElementEngine.hpp"
#include "FlexMat.hpp"
#include "FlexNewtonIntegrator.hpp"
#include "FlexNode.hpp"
#include "FlexTimeStepper.hpp"
