//! Cutting one output vector into the disjoint parts that parallel tasks fill.

/// Cut the first `n` items off `slice`, leaving the rest in it.
pub(crate) fn cut<'a, T>(slice: &mut &'a mut [T], n: usize) -> &'a mut [T] {
    let (head, tail) = std::mem::take(slice).split_at_mut(n);
    *slice = tail;
    head
}

/// `slice` cut into consecutive parts of the given `lengths` (which add up to at
/// most its length), to be filled in parallel.
pub(crate) fn split_into<T>(
    mut slice: &mut [T],
    lengths: impl Iterator<Item = usize>,
) -> Vec<&mut [T]> {
    lengths.map(|length| cut(&mut slice, length)).collect()
}
