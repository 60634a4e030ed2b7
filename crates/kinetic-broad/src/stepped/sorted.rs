//! Sorted sets (of pairs, of box indices): their merge and their difference.

/// `a` and `b`, sorted and disjoint, merged into `out`, sorted.
pub(crate) fn merge<T: Ord + Copy>(a: &[T], b: &[T], out: &mut Vec<T>) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if a[i] <= b[j] {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
}

/// What takes sorted, distinct `old` to sorted, distinct `new`, in one pass, in order:
/// `gone` is called with each item only in `old`, `came` with each only in `new`.
pub(crate) fn sorted_difference<T: Ord + Copy>(
    old: &[T],
    new: &[T],
    mut gone: impl FnMut(T),
    mut came: impl FnMut(T),
) {
    let (mut i, mut j) = (0, 0);
    while i < old.len() || j < new.len() {
        match (old.get(i), new.get(j)) {
            (Some(x), Some(y)) if x == y => {
                i += 1;
                j += 1;
            }
            (Some(&x), y) if y.is_none_or(|&y| x < y) => {
                gone(x);
                i += 1;
            }
            (_, Some(&y)) => {
                came(y);
                j += 1;
            }
            _ => break,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_difference_and_the_merge_of_sorted_sets() {
        let (old, new) = ([1, 3, 5, 7], [2, 3, 7, 8, 9]);
        let (mut gone, mut came) = (Vec::new(), Vec::new());
        sorted_difference(&old, &new, |x| gone.push(x), |y| came.push(y));
        assert_eq!((gone, came), (vec![1, 5], vec![2, 8, 9]));
        let mut out = Vec::new();
        merge(&[1, 4, 6], &[2, 3, 9], &mut out);
        assert_eq!(out, [1, 2, 3, 4, 6, 9]);
    }
}
