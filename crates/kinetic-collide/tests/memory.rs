//! A streamed run's memory does not grow with its number of events: the peak of the heap,
//! counted by a wrapping allocator, is the same for a run fifteen times as long.

use kinetic_collide::ContactEvent;
use kinetic_collide::Structure;
use kinetic_collide::run::{Stream, run_scene_streamed};
use kinetic_scenes::HardSpheres;
use std::alloc::{GlobalAlloc, Layout, System};
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes in use and their peak.
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed on to the system allocator unchanged; only counters are added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is the system allocator's.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = IN_USE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) };
        IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The heap's peak over a streamed run of a 2,000-sphere gas (in walls, or in a periodic box
/// for the periodic structure) for about `collisions` collisions with `structure`, and the
/// events the sink saw.
fn peak_of_run(collisions: f64, structure: Structure) -> (usize, u64) {
    let scene = HardSpheres {
        collisions,
        periodic: structure == Structure::Periodic,
        ..HardSpheres::gas(2000)
    }
    .build()
    .unwrap();
    let mut seen = 0u64;
    let mut last = 0.0f64;
    let mut sink = |batch: &[ContactEvent]| {
        for e in batch {
            assert!(e.time >= last);
            last = e.time;
        }
        seen += batch.len() as u64;
        ControlFlow::Continue(())
    };
    let mut stream = Stream {
        sink: &mut sink,
        stop: None,
    };
    let base = IN_USE.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let out =
        run_scene_streamed(&scene, Some(structure), &[], &mut |_, _| {}, &mut stream).unwrap();
    assert!(out.events.is_empty());
    assert_eq!(out.stats.begins, seen);
    drop(scene);
    (PEAK.load(Ordering::Relaxed) - base, seen)
}

#[test]
fn a_streamed_run_holds_no_more_for_more_events() {
    for structure in [Structure::Cells, Structure::Grid, Structure::Periodic] {
        let (short, short_events) = peak_of_run(2e4, structure);
        let (long, long_events) = peak_of_run(3e5, structure);
        assert!(
            long_events > 10 * short_events,
            "{long_events} vs {short_events}"
        );
        // Holding the events would add 24 bytes each: 6 MB over the long run's extra 2.6e5.
        assert!(
            long < short + short / 10 + (1 << 20),
            "{structure:?}: peak {long} bytes over {long_events} events, {short} over {short_events}"
        );
    }
}
