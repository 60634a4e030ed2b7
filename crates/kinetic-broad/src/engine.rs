//! What the broad phase asks of a physics engine, and what it hands back.

use crate::{Aabb, Bound, Slack};
use kinetic_core::{Real, Vec3};

/// An engine's key for a collider or a body: a dense index that the engine may reuse once the
/// thing is gone, and a generation that tells a reused index apart. Rapier's handles and
/// Bevy's entities are both of this kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Key {
    /// The index: the broad phase keeps a slot per index, so keep them dense.
    pub index: u32,
    /// The generation of the index.
    pub generation: u32,
}

impl Key {
    /// The key of index `index` in generation `generation`.
    pub const fn new(index: u32, generation: u32) -> Key {
        Key { index, generation }
    }
}

/// What the engine says of a collider the broad phase asks about.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColliderStatus {
    /// The engine has no such collider (it was removed and its removal comes later).
    Missing,
    /// The collider is there but takes no part in collisions: it is dropped.
    Disabled,
    /// The collider and how it is held now ([`Bound::moving`] or [`Bound::fixed`]).
    Held(Bound),
}

/// A moving body as the engine has it now.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// Its centre of mass in world space, at its current pose.
    pub centre: Vec3,
    /// Its linear velocity.
    pub velocity: Vec3,
    /// Whether the engine has put it to sleep.
    pub sleeping: bool,
}

/// The engine's view of its colliders and bodies, asked during an update.
pub trait Engine {
    /// How collider `c` is held now, with `slack` for a moving body.
    fn collider(&self, c: Key, slack: Slack) -> ColliderStatus;
    /// How collider `c` is held, for a world that steps on the engine's enlarged boxes for
    /// good ([`Engine::enlarged`]): such a world reads of a collider on a moving body only
    /// which body it is, never its ball, so an engine may leave the radius and slack at zero
    /// rather than work out the collider's reach (a hull's bounding sphere), as long as it
    /// always does. The default asks [`Engine::collider`].
    fn collider_on_boxes(&self, c: Key) -> ColliderStatus {
        self.collider(c, Slack::NONE)
    }
    /// Body `b`'s state, or `None` if the engine has no such body.
    fn body(&self, b: Key) -> Option<BodyState>;
    /// Body `b`'s centre of mass and linear velocity, as [`Engine::body`] gives them: all a
    /// position update reads of each moved body. An engine may read them from less of its
    /// memory than the whole state.
    fn motion(&self, b: Key) -> Option<(Vec3, Vec3)> {
        self.body(b).map(|s| (s.centre, s.velocity))
    }
    /// [`Engine::motion`] of each of `bodies`, in order, pushed onto `out`: all a position
    /// update reads of the engine's bodies, in one pass. An engine may ask for the bodies a
    /// few ahead of the one it reads ([`kinetic_core::prefetch`]), so that their reads
    /// overlap.
    fn motions(&self, bodies: &[Key], out: &mut Vec<Option<(Vec3, Vec3)>>) {
        out.extend(bodies.iter().map(|&b| self.motion(b)));
    }
    /// Collider `c`'s axis-aligned box now, grown by the margins the engine grows it by (its
    /// contact prediction distance). An engine that gives it lets bodies in contact be held
    /// by fat boxes (see the crate docs); the default, `None`, keeps every moving body on a
    /// flight plan.
    fn bounds(&self, c: Key) -> Option<Aabb> {
        let _ = c;
        None
    }
    /// Asks for what [`Engine::bounds`] of collider `c` reads to be fetched: a position
    /// update that moved thousands of colliders (more than a core's caches hold) calls it for
    /// the collider a few ahead of the one whose box it reads, so that their reads overlap
    /// ([`kinetic_core::prefetch`]). A hint, which changes no result; the default does
    /// nothing.
    fn prefetch_collider(&self, c: Key) {
        let _ = c;
    }
    /// How far ahead the engine's narrow phase looks for body `b`, given `d`, the move the
    /// broad phase expects of it over the coming step: two boxes ([`Engine::bounds`]) that
    /// do not overlap now make a pair of the engine's when they meet swept by these moves.
    /// The default, `d`: the pair is the engine's when the boxes meet at any moment of the
    /// step. An engine that tests its pairs at the poses it has now returns zero (rapier,
    /// whose own broad phase takes the boxes where they are), or the move cut to what it
    /// predicts (rapier's soft CCD). Asked only for moving bodies (in a stepped world, only
    /// for candidates whose boxes do not overlap now).
    fn ahead(&self, b: Key, d: Vec3) -> Vec3 {
        let _ = b;
        d
    }
    /// Collider `c`'s enlarged box, if the engine keeps one as its own broad phase does: a
    /// box about [`Engine::bounds`] that the engine moves only when the collider leaves it
    /// (avian's `EnlargedAabb`). A stepped world then files this box as it is, unswept, and
    /// reads it again only for the colliders the engine lists as moved, so that a body
    /// jostling inside its box costs nothing; the engine must then list as moved every
    /// collider whose enlarged box it moved (and every awake one while
    /// [`crate::BroadPhaseCore::reads_every_move`] says so). The default, `None`: boxes are
    /// read for every moved collider and swept over the step.
    fn enlarged(&self, c: Key) -> Option<Aabb> {
        let _ = c;
        None
    }

    /// The indices of the colliders whose enlarged boxes ([`Engine::enlarged`]) may overlap
    /// `b`, collider `c`'s enlarged box as the broad phase has it, pushed onto `out` (a
    /// superset: each is tested again; `c` itself may come), from an index of those boxes
    /// that the engine keeps for its own use (avian's collider trees). The stepped world
    /// then looks up each moved collider there instead of filing the boxes again itself.
    /// The default, `false`: the engine keeps no such index.
    fn enlarged_near(&self, c: Key, b: &Aabb, out: &mut Vec<u32>) -> bool {
        let _ = (c, b, out);
        false
    }
}

/// The engine's step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EngineStep {
    /// Its length in time.
    pub dt: Real,
    /// How many substeps its integrator splits it into (1 for none): the plans are fitted
    /// to that integrator ([`crate::fit_plan`]).
    pub substeps: Real,
}

/// What an update asks the engine to do with a pair of colliders; the lower index comes
/// first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum PairEvent {
    /// The two colliders' proxies can meet within the step: test the pair.
    Add(Key, Key),
    /// They cannot any more: the pair can go.
    Delete(Key, Key),
}
