//! Live pairs into avian's contact graph, filtered as avian's own broad phase filters them.

use crate::view::{AvianWorld, entity};
use avian3d::collider_tree::{ColliderTreeProxyFlags, ColliderTreeType};
use avian3d::collision::contact_types::ContactEdgeFlags;
use avian3d::prelude::*;
use bevy::prelude::*;
use kinetic_broad::Key;

/// Adds to `graph` every pair of `pairs` (live ones, each once) whose colliders' enlarged
/// boxes overlap and that it does not hold, unless avian's broad phase would filter it out;
/// returns how many were added, and pushes onto `in_graph` whether each pair is in the graph
/// now.
pub(crate) fn add_overlapping(
    pairs: &[(Key, Key)],
    world: &AvianWorld,
    hooks: &impl CollisionHooks,
    commands: &mut Commands,
    graph: &mut ContactGraph,
    in_graph: &mut Vec<bool>,
) -> u64 {
    let mut added = 0;
    // The pairs come grouped by their first collider: it is read once a group, and only
    // for a pair the graph does not hold (most of them it does).
    let mut first = None;
    for &(a, b) in pairs {
        let (Some(e1), Some(e2)) = (entity(a), entity(b)) else {
            in_graph.push(false);
            continue;
        };
        if graph.contains(e1, e2) {
            in_graph.push(true);
            continue;
        }
        // Left out unless added below.
        in_graph.push(false);
        if first.is_none_or(|(k, _)| k != a) {
            first = Some((a, world.collider_view(a)));
        }
        let (Some(c1), Some(c2)) = (first.and_then(|f| f.1), world.collider_view(b)) else {
            continue;
        };
        if !c1.enlarged.intersects(&c2.enlarged.get()) {
            continue;
        }
        let (Some(k1), Some(k2)) = (c1.proxy, c2.proxy) else {
            continue;
        };
        let (Some(p1), Some(p2)) = (world.trees.get_proxy(k1), world.trees.get_proxy(k2)) else {
            continue;
        };
        // Two static colliders only when a sensor is involved.
        let fixed = |t: ColliderTreeType| t == ColliderTreeType::Static;
        if fixed(k1.tree_type()) && fixed(k2.tree_type()) && !p1.is_sensor() && !p2.is_sensor() {
            continue;
        }
        if !p1.layers.interacts_with(p2.layers) || p1.body == p2.body {
            continue;
        }
        if let (Some(b1), Some(b2)) = (p1.body, p2.body)
            && world
                .joints
                .joints_between(b1, b2)
                .any(|edge| edge.collision_disabled)
        {
            continue;
        }
        let flags = p1.flags.union(p2.flags);
        if flags.contains(ColliderTreeProxyFlags::CUSTOM_FILTER)
            && !hooks.filter_pairs(c1.entity, c2.entity, commands)
        {
            continue;
        }
        let mut edge = ContactEdge::new(c1.entity, c2.entity);
        edge.body1 = p1.body;
        edge.body2 = p2.body;
        edge.flags.set(
            ContactEdgeFlags::CONTACT_EVENTS,
            flags.contains(ColliderTreeProxyFlags::CONTACT_EVENTS),
        );
        graph.add_edge_with(edge, |pair| {
            pair.body1 = p1.body;
            pair.body2 = p2.body;
            pair.flags.set(
                ContactPairFlags::MODIFY_CONTACTS,
                flags.contains(ColliderTreeProxyFlags::MODIFY_CONTACTS),
            );
            pair.flags.set(
                ContactPairFlags::GENERATE_CONSTRAINTS,
                !flags.contains(ColliderTreeProxyFlags::BODY_DISABLED)
                    && !flags.contains(ColliderTreeProxyFlags::SENSOR),
            );
        });
        *in_graph.last_mut().expect("pushed") = true;
        added += 1;
    }
    added
}
