//! avian's colliders and bodies as the core sees them: entities as [`Key`]s, the ECS queries
//! as an [`Engine`], and the changes since the last step.

use avian3d::collider_tree::{ColliderTreeProxyKey, ColliderTreeType, ColliderTrees, MovedProxies};
use avian3d::collision::collider::EnlargedAabb;
use avian3d::dynamics::joints::joint_graph::JointGraph;
use avian3d::prelude::*;
use bevy::ecs::entity::EntityGeneration;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use kinetic_broad::{
    Aabb, BodyState, Bound, BroadPhaseCore, ColliderStatus, Engine, EngineStep, Key, Slack,
};
use kinetic_core::{Real, Vec3};

/// An entity as a key: its index and generation.
pub(crate) fn key(e: Entity) -> Key {
    Key::new(e.index_u32(), e.generation().to_bits())
}

/// The entity of a key.
pub(crate) fn entity(k: Key) -> Option<Entity> {
    let index = Entity::from_raw_u32(k.index)?.index();
    Some(Entity::from_index_and_generation(
        index,
        EntityGeneration::from_bits(k.generation),
    ))
}

/// Any of avian's 3-vectors (f32, or f64 positions) in the core's f64.
macro_rules! dvec {
    ($v:expr) => {{
        let a = $v.to_array();
        Vec3::new(a[0] as Real, a[1] as Real, a[2] as Real)
    }};
}

type ColliderItem = (
    &'static Collider,
    &'static Position,
    &'static Rotation,
    &'static ColliderAabb,
    Option<&'static ColliderOf>,
    Option<&'static CollisionMargin>,
    Has<ColliderDisabled>,
);

type BodyItem = (
    &'static RigidBody,
    &'static Position,
    &'static Rotation,
    &'static ComputedCenterOfMass,
    &'static LinearVelocity,
    Has<Sleeping>,
);

/// The colliders and bodies whose immutable components were inserted since the last step
/// (a body, layers, a body type) or that were made sensors or disabled, as observers see
/// them: no query then looks at every collider for these each step.
#[derive(Resource, Default)]
pub(crate) struct Inserted {
    colliders: Vec<Entity>,
    bodies: Vec<Entity>,
    /// Whether a change since the last step may have taken pairs out of the contact graph
    /// (a body disabled, enabled or made no body: avian drops its colliders' pairs).
    recheck: bool,
}

/// Notes the insertions the broad phase acts on (`ColliderOf`, `CollisionLayers`, `Sensor`,
/// `ColliderDisabled` on colliders, `RigidBody` on bodies: each immutable or a marker, so an
/// insertion is their only change), a sensor made a plain collider again, and the changes
/// that take pairs out of avian's contact graph.
pub(crate) fn observe_insertions(app: &mut App) {
    app.init_resource::<Inserted>();
    macro_rules! note {
        ($event:ty, $list:ident) => {
            app.add_observer(|on: On<$event>, mut inserted: ResMut<Inserted>| {
                inserted.$list.push(on.entity);
            });
        };
    }
    note!(Insert<ColliderOf>, colliders);
    note!(Insert<CollisionLayers>, colliders);
    note!(Add<Sensor>, colliders);
    // avian takes a collider's pairs out of its contact graph when it stops being a sensor.
    note!(Remove<Sensor>, colliders);
    note!(Add<ColliderDisabled>, colliders);
    note!(Insert<RigidBody>, bodies);
    macro_rules! recheck {
        ($($event:ty),*) => {$(
            app.add_observer(|_: On<$event>, mut inserted: ResMut<Inserted>| {
                inserted.recheck = true;
            });
        )*};
    }
    recheck!(
        Add<RigidBodyDisabled>,
        Remove<RigidBodyDisabled>,
        Add<bevy::ecs::entity_disabling::Disabled>,
        Remove<bevy::ecs::entity_disabling::Disabled>,
        Remove<RigidBody>
    );
}

/// Colliders that moved, and their bodies.
type Placed = (Entity, Option<&'static ColliderOf>);

/// What a look-up in avian's trees reads of a collider: its enlarged box, tree proxy and
/// whether it is disabled (a narrower query than [`ColliderItem`], read for every box moved).
type BoxItem = (
    &'static EnlargedAabb,
    Option<&'static ColliderTreeProxyKey>,
    Has<ColliderDisabled>,
);

/// avian's world as the broad phase reads it.
#[derive(SystemParam)]
pub(crate) struct AvianWorld<'w, 's> {
    colliders: Query<'w, 's, ColliderItem>,
    boxes: Query<'w, 's, BoxItem>,
    bodies: Query<'w, 's, BodyItem>,
    /// What [`Engine::collider_on_boxes`] reads of a collider: its body and whether it is
    /// disabled.
    riding: Query<'w, 's, (Option<&'static ColliderOf>, Has<ColliderDisabled>), With<Collider>>,
    all: Query<'w, 's, Entity, With<Collider>>,
    pub(crate) trees: Res<'w, ColliderTrees>,
    /// The tree proxies whose enlarged boxes avian moved since the last broad phase.
    moved_proxies: Res<'w, MovedProxies>,
    pub(crate) joints: Res<'w, JointGraph>,
    time: Res<'w, Time>,
    substeps: Res<'w, SubstepCount>,
    length_unit: Res<'w, PhysicsLengthUnit>,
    config: Res<'w, NarrowPhaseConfig>,
}

/// What the graph needs of a collider: its entity, enlarged box and tree proxy.
#[derive(Clone, Copy)]
pub(crate) struct ColliderView<'a> {
    pub(crate) entity: Entity,
    pub(crate) enlarged: &'a EnlargedAabb,
    pub(crate) proxy: Option<ColliderTreeProxyKey>,
}

impl AvianWorld<'_, '_> {
    /// The step: avian's physics time step and its substeps.
    pub(crate) fn step(&self) -> EngineStep {
        EngineStep {
            dt: self.time.delta_secs_f64() as Real,
            substeps: self.substeps.0.max(1) as Real,
        }
    }

    /// Every collider's key.
    pub(crate) fn collider_keys(&self) -> Vec<Key> {
        self.all.iter().map(key).collect()
    }

    /// The colliders whose enlarged boxes (`EnlargedAabb`) avian moved since the last broad
    /// phase, those of fixed ones (static bodies, or none: moved by the user) for `fixed`:
    /// avian's own broad phase looks only at these, and a pair of two others keeps whether
    /// their enlarged boxes overlap.
    pub(crate) fn enlarged_moved(&self, fixed: bool) -> impl Iterator<Item = Key> + '_ {
        self.moved_proxies
            .proxies()
            .iter()
            .filter(move |k| {
                let t = k.tree_type();
                fixed == (t == ColliderTreeType::Static || t == ColliderTreeType::Standalone)
            })
            .filter_map(|&k| self.trees.get_proxy(k))
            .map(|p| key(p.collider))
    }

    /// Collider `k`, if it is there and enabled.
    pub(crate) fn collider_view(&self, k: Key) -> Option<ColliderView<'_>> {
        let e = entity(k)?;
        let (enlarged, proxy, disabled) = self.boxes.get(e).ok()?;
        (!disabled).then_some(ColliderView {
            entity: e,
            enlarged,
            proxy: proxy.copied(),
        })
    }

    /// Whether body `b` sleeps.
    pub(crate) fn is_sleeping(&self, b: Entity) -> bool {
        self.bodies.get(b).is_ok_and(|item| item.5)
    }

    /// Whether entity `e` is a static body (or no body).
    pub(crate) fn is_static_body(&self, e: Option<Entity>) -> bool {
        e.and_then(|b| self.bodies.get(b).ok())
            .is_none_or(|(rb, ..)| rb.is_static())
    }

    /// How far avian grows a collider's box: the contact tolerance and its collision margin.
    fn margin(&self, collision_margin: Option<&CollisionMargin>) -> Real {
        (self.length_unit.0 * self.config.contact_tolerance) as Real
            + collision_margin.map_or(0.0, |m| m.0 as Real)
    }
}

impl Engine for AvianWorld<'_, '_> {
    fn collider(&self, c: Key, slack: Slack) -> ColliderStatus {
        let Some(e) = entity(c) else {
            return ColliderStatus::Missing;
        };
        let Ok((collider, pos, rot, _, of, margin, disabled)) = self.colliders.get(e) else {
            return ColliderStatus::Missing;
        };
        if disabled {
            return ColliderStatus::Disabled;
        }
        let margin = self.margin(margin);
        let moving = of
            .and_then(|of| self.bodies.get(of.body).ok().map(|b| (of.body, b)))
            .filter(|(_, (rb, ..))| !rb.is_static());
        match moving {
            None => {
                let aabb = collider.aabb(pos.0, *rot, 0.0);
                ColliderStatus::Held(Bound::fixed(dvec!(aabb.min), dvec!(aabb.max), margin))
            }
            Some((body, (_, bpos, brot, com, ..))) => {
                let centre = dvec!(bpos.0) + dvec!(brot.0 * com.0);
                let sphere = collider.shape_scaled().compute_local_bounding_sphere();
                // In the core's f64: the shape's centre is parry's (f32 or f64), the rotation
                // avian's.
                let q = rot.0;
                let q = kinetic_core::Quat::from_xyzw(
                    q.x as Real,
                    q.y as Real,
                    q.z as Real,
                    q.w as Real,
                );
                let offset = q * dvec!(sphere.center());
                let reach = (dvec!(pos.0) + offset - centre).length() + sphere.radius() as Real;
                let slack = Slack {
                    min: slack.min * self.length_unit.0 as Real,
                    ..slack
                };
                ColliderStatus::Held(Bound::moving(key(body), reach, margin, slack))
            }
        }
    }

    /// The body a collider on a moving body rides, without its reach (a world on avian's
    /// enlarged boxes reads no more), or the box of a fixed one.
    fn collider_on_boxes(&self, c: Key) -> ColliderStatus {
        let Some((of, disabled)) = entity(c).and_then(|e| self.riding.get(e).ok()) else {
            return ColliderStatus::Missing;
        };
        if disabled {
            return ColliderStatus::Disabled;
        }
        let moving = of
            .map(|of| of.body)
            .filter(|&b| self.bodies.get(b).is_ok_and(|(rb, ..)| !rb.is_static()));
        match moving {
            Some(body) => ColliderStatus::Held(Bound::Moving {
                body: key(body),
                radius: 0.0,
                slack: 0.0,
            }),
            None => self.collider(c, Slack::NONE),
        }
    }

    /// avian's own box of the collider (`ColliderAabb`, grown by its contact tolerance and
    /// collision margin, swept where speculative CCD asks), as avian's tree upkeep left it
    /// before the broad phase runs; computed here only for a box avian has not filled yet.
    fn bounds(&self, c: Key) -> Option<Aabb> {
        let (collider, pos, rot, aabb, _, margin, disabled) =
            self.colliders.get(entity(c)?).ok()?;
        if disabled {
            return None;
        }
        let (min, max) = (dvec!(aabb.min), dvec!(aabb.max));
        if min.is_finite() && max.is_finite() && min.cmple(max).all() {
            return Some(Aabb::new(min, max));
        }
        let aabb = collider.aabb(pos.0, *rot, 0.0);
        let m = Vec3::splat(self.margin(margin));
        Some(Aabb::new(dvec!(aabb.min), dvec!(aabb.max)).grown(m))
    }

    /// avian's `EnlargedAabb` of the collider: its own broad phase's box, moved only when
    /// the collider's box leaves it (the pairs avian's narrow phase keeps are those whose
    /// enlarged boxes overlap).
    fn enlarged(&self, c: Key) -> Option<Aabb> {
        let (enlarged, _, disabled) = self.boxes.get(entity(c)?).ok()?;
        let (min, max) = (dvec!(enlarged.min), dvec!(enlarged.max));
        (!disabled && min.is_finite() && max.is_finite() && min.cmple(max).all())
            .then(|| Aabb::new(min, max))
    }

    /// The colliders in avian's collider trees whose boxes overlap `b` (collider `c`'s
    /// enlarged box, rounded to single precision, grown by a little more than that
    /// rounding): avian keeps the trees up to date for its queries whichever broad phase
    /// runs.
    fn enlarged_near(&self, _c: Key, b: &Aabb, out: &mut Vec<u32>) -> bool {
        let f = |v: Vec3| bevy::math::Vec3A::new(v.x as f32, v.y as f32, v.z as f32);
        let (min, max) = (f(b.min), f(b.max));
        let pad = min.abs().max(max.abs()) * 1e-6 + 1e-30;
        let q = obvhs::aabb::Aabb::new(min - pad, max + pad);
        for tree in self.trees.iter_trees() {
            tree.aabb_traverse(q, |id| {
                if let Some(p) = tree.get_proxy(id) {
                    out.push(p.collider.index_u32());
                }
                true
            });
        }
        true
    }

    fn body(&self, b: Key) -> Option<BodyState> {
        let (_, pos, rot, com, v, sleeping) = self.bodies.get(entity(b)?).ok()?;
        Some(BodyState {
            centre: dvec!(pos.0) + dvec!(rot.0 * com.0),
            velocity: dvec!(v.0),
            sleeping,
        })
    }
}

/// The changes since the last step, read through Bevy's change detection.
#[derive(SystemParam)]
pub(crate) struct Changes<'w, 's> {
    /// Colliders added or whose shape changed (the one mutable component of those read).
    changed: Query<'w, 's, Entity, (With<Collider>, Changed<Collider>)>,
    /// Colliders and bodies whose other components were inserted.
    inserted: ResMut<'w, Inserted>,
    /// Colliders that moved: those on static bodies (or none) were moved by the user.
    placed: Query<'w, 's, Placed, (With<Collider>, Changed<Position>)>,
    /// The colliders of each body.
    held: Query<'w, 's, &'static RigidBodyColliders>,
    /// Bodies that move and are awake.
    awake: Query<'w, 's, (&'static RigidBody, &'static RigidBodyColliders), Without<Sleeping>>,
    removed: RemovedComponents<'w, 's, Collider>,
    enabled: RemovedComponents<'w, 's, ColliderDisabled>,
    /// The colliders changed, gathered once each.
    modified: Local<'s, KeySet>,
}

/// Which moved colliders a call asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Moves {
    /// None (the first call: every collider is new).
    None,
    /// Every collider on a body that moves and is awake, and those of bodies that fell
    /// asleep since the last call (the core reads every moved body).
    Every,
    /// Those whose enlarged boxes avian moved.
    Enlarged,
}

/// Keys gathered once each, handed back sorted: on the first step every collider comes
/// several times over (its insertions and its body's), and sorting them all to drop the
/// repeats cost the first step's broad phase a tenth of its time.
#[derive(Default)]
pub(crate) struct KeySet {
    /// Per entity index, the generation held plus one (0: none).
    held: Vec<u64>,
    keys: Vec<Key>,
    /// Keys whose index is held in another generation (an entity despawned and its index
    /// taken again since the last call): rare, sorted with the rest.
    others: Vec<Key>,
}

impl KeySet {
    /// Adds `k` unless it is held.
    fn push(&mut self, k: Key) {
        let i = k.index as usize;
        if self.held.len() <= i {
            self.held.resize(i + 1, 0);
        }
        let g = u64::from(k.generation) + 1;
        match self.held[i] {
            0 => {
                self.held[i] = g;
                self.keys.push(k);
            }
            h if h == g => {}
            _ => self.others.push(k),
        }
    }

    /// The keys held, sorted, each once; the set is left empty.
    fn take_sorted(&mut self) -> Vec<Key> {
        let mut keys = std::mem::take(&mut self.keys);
        if keys.len() * 16 < self.held.len() {
            // A few: sorted as they are.
            for k in &keys {
                self.held[k.index as usize] = 0;
            }
            keys.sort_unstable();
        } else {
            // Many against the indices: read off in index order.
            keys.clear();
            for (i, h) in self.held.iter_mut().enumerate() {
                if *h != 0 {
                    keys.push(Key::new(i as u32, (*h - 1) as u32));
                    *h = 0;
                }
            }
        }
        if !self.others.is_empty() {
            keys.append(&mut self.others);
            keys.sort_unstable();
            keys.dedup();
        }
        keys
    }
}

impl Extend<Key> for KeySet {
    fn extend<I: IntoIterator<Item = Key>>(&mut self, keys: I) {
        for k in keys {
            self.push(k);
        }
    }
}

impl Changes<'_, '_> {
    /// Whether a change since the last call may have taken pairs out of the contact graph
    /// unseen by the pairs' colliders.
    pub(crate) fn take_recheck(&mut self) -> bool {
        std::mem::take(&mut self.inserted.recheck)
    }

    /// The colliders changed by the user (or new), those removed, and those moved, as
    /// `moves` asks for them.
    pub(crate) fn collect(
        &mut self,
        world: &AvianWorld,
        core: &BroadPhaseCore,
        moves: Moves,
    ) -> (Vec<Key>, Vec<Key>, Vec<Key>) {
        let modified = &mut *self.modified;
        let inserted = &mut *self.inserted;
        if moves == Moves::None {
            // The first call: every collider is new.
            inserted.colliders.clear();
            inserted.bodies.clear();
            modified.extend(world.all.iter().map(key));
        } else {
            modified.extend(self.changed.iter().map(key));
            // Those inserted on colliders still there, and the colliders of retyped bodies.
            let there = |e: &Entity| world.all.contains(*e);
            modified.extend(inserted.colliders.drain(..).filter(there).map(key));
            for body in inserted.bodies.drain(..) {
                if let Ok(colliders) = self.held.get(body) {
                    modified.extend(colliders.iter().map(key));
                }
            }
        }
        let mut moved = Vec::new();
        match moves {
            Moves::None => {}
            // What avian's own box upkeep saw move: the fixed colliders the user moved out
            // of their enlarged boxes (one moved within its box keeps it, as in avian's own
            // broad phase) and the moving ones.
            Moves::Enlarged => {
                modified.extend(world.enlarged_moved(true));
                moved.extend(world.enlarged_moved(false));
            }
            Moves::Every => {
                for (e, of) in &self.placed {
                    let k = key(e);
                    let body = of.map(|of| of.body);
                    // A collider held on a moving body: its moves come with the body's.
                    let known = core.on_moving_body(k);
                    if !known && world.is_static_body(body) {
                        modified.push(k);
                    } else if body.is_some_and(|b| world.is_sleeping(b)) {
                        // Moved in the last step, then fell asleep (or was put to sleep)
                        // before this call: its box is where the step left it.
                        moved.push(k);
                    }
                }
                for (rb, colliders) in &self.awake {
                    if !rb.is_static() {
                        moved.extend(colliders.iter().map(key));
                    }
                }
            }
        }
        modified.extend(self.enabled.read().map(key));
        let modified = modified.take_sorted();
        let mut removed: Vec<Key> = self.removed.read().map(key).collect();
        removed.sort_unstable();
        removed.dedup();
        (modified, removed, moved)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Keys come back sorted and each once, whether few against the indices seen or many,
    /// an index taken again in another generation included; the set is then empty.
    #[test]
    fn a_key_set_gives_each_key_once_in_order() {
        let mut set = KeySet::default();
        for many in [false, true] {
            let mut want = Vec::new();
            // Few: 4 keys among 76 indices; many: 100 among 100.
            let (top, apart) = if many { (100, 1) } else { (4, 25) };
            for i in (0..top).rev() {
                let k = Key::new(i * apart, 1);
                set.extend([k, k]);
                want.push(k);
            }
            // Index 0 in another generation, and in the first again.
            set.extend([Key::new(0, 7), Key::new(0, 1), Key::new(0, 7)]);
            want.push(Key::new(0, 7));
            want.sort_unstable();
            want.dedup();
            assert_eq!(set.take_sorted(), want, "many: {many}");
            assert!(set.take_sorted().is_empty());
        }
    }
}
