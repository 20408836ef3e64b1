#pragma once
// The element kinds of a torsional network, one row each: the YAML type and
// ElementKind name, the element type (lib/tvid/model/elements/NAME.hpp) and the
// NetworkSpec list that holds them. NetworkSpec's lists, ElementKind, NetworkModel's
// storage and every walk over elements come from this table.
//
// The rows' order is the order in which the right-hand side sums the elements'
// torques into each node (and so part of its floating-point result): keep it.
//
// Adding an element kind: write elements/NAME.hpp (as spring_damper.hpp: its spec; its
// type name, keys and read(); its field table with each field's unit; the channel it reads;
// the outputs it offers; its linearisation; its bound form, torque formula and node
// loading) and add its row here. Nothing else names a kind: the reader, the units, the
// linearisation and the outputs walk this table, and a kind that leaves out a rule does
// not compile (DescribedElementKind, network_spec.hpp).

#include "tvid/model/elements/clearance.hpp"
#include "tvid/model/elements/cylinder.hpp"
#include "tvid/model/elements/friction.hpp"
#include "tvid/model/elements/gear_mesh.hpp"
#include "tvid/model/elements/ideal_gear.hpp"
#include "tvid/model/elements/multistage_spring.hpp"
#include "tvid/model/elements/order_torque.hpp"
#include "tvid/model/elements/position_controller.hpp"
#include "tvid/model/elements/road_load.hpp"
#include "tvid/model/elements/speed_source.hpp"
#include "tvid/model/elements/spring_damper.hpp"
#include "tvid/model/elements/torque.hpp"

//     X(kind,          Type,         list in NetworkSpec)
#define TVID_ELEMENT_KINDS(X)                      \
    X(spring_damper, SpringDamper, spring_dampers) \
    X(clearance, Clearance, clearances)            \
    X(friction, Friction, frictions)               \
    X(gear_mesh, GearMesh, gear_meshes)            \
    X(torque, Torque, torques)                     \
    X(cylinder, Cylinder, cylinders)               \
    X(order_torque, OrderTorque, order_torques)    \
    X(speed_source, SpeedSource, speed_sources)    \
    X(road_load, RoadLoad, road_loads)             \
    X(multistage_spring, MultistageSpring, multistage_springs) \
    X(position_controller, PositionController, position_controllers) \
    X(ideal_gear, IdealGear, ideal_gears)
