//! The event queue against a sorted vector.

use kinetic_core::kds::EventQueue;
use proptest::prelude::*;

#[derive(Clone, Debug)]
enum Op {
    Schedule(u32, u8, u8),
    Remove(u32),
    Pop,
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        (0u32..40, 0u8..16, 0u8..3).prop_map(|(id, t, tie)| Op::Schedule(id, t, tie)),
        (0u32..40).prop_map(Op::Remove),
        Just(Op::Pop),
    ]
}

proptest! {
    #[test]
    fn queue_matches_a_sorted_vector(ops in prop::collection::vec(op(), 1..300)) {
        let mut q = EventQueue::new();
        // (time, tie, id), kept sorted: the reference.
        let mut model: Vec<(f64, u64, u32)> = Vec::new();
        for op in ops {
            match op {
                Op::Schedule(id, t, tie) => {
                    let t = f64::from(t) * 0.5;
                    q.schedule(id, t, u64::from(tie));
                    model.retain(|e| e.2 != id);
                    model.push((t, u64::from(tie), id));
                }
                Op::Remove(id) => {
                    let got = q.remove(id);
                    let want = model.iter().position(|e| e.2 == id).map(|i| model.remove(i).0);
                    prop_assert_eq!(got, want);
                }
                Op::Pop => {
                    model.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
                    let want = if model.is_empty() { None } else { let e = model.remove(0); Some((e.2, e.0)) };
                    prop_assert_eq!(q.pop(), want);
                }
            }
            prop_assert_eq!(q.len(), model.len());
            q.validate().map_err(TestCaseError::fail)?;
        }
    }
}

#[test]
fn equal_times_pop_by_tie_then_id() {
    let mut q = EventQueue::new();
    for (id, tie) in [(5, 2), (1, 2), (9, 0), (3, 1)] {
        q.schedule(id, 1.0, tie);
    }
    let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|e| e.0)).collect();
    assert_eq!(order, vec![9, 3, 1, 5]);
}
