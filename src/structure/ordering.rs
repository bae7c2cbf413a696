//! DOF numbering strategies: the order in which a structure's nodes are numbered.
//!
//! The assembled matrices are factored as skylines (profile LDLᵀ), whose cost grows with
//! the square of each row's reach back to its first non-zero. A beam numbered along its
//! axis already has the smallest profile; a two-dimensional mesh gets reverse
//! Cuthill–McKee, which numbers it front by front from a peripheral node so each row
//! reaches back about one front.

/// Reverse Cuthill–McKee order of a graph given by its adjacency lists (`adjacent[v]`, no
/// self loops needed). Every component is ordered from a pseudo-peripheral start node.
pub fn reverse_cuthill_mckee(adjacent: &[Vec<usize>]) -> Vec<usize> {
    let n = adjacent.len();
    let degree = |v: usize| adjacent[v].len();
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    while order.len() < n {
        let seed = (0..n).filter(|&v| !placed[v]).min_by_key(|&v| degree(v)).expect("an unplaced node");
        let start = peripheral(adjacent, seed);
        let first = order.len();
        order.push(start);
        placed[start] = true;
        let mut head = first;
        while head < order.len() {
            let v = order[head];
            head += 1;
            let mut next: Vec<usize> = adjacent[v].iter().copied().filter(|&u| !placed[u]).collect();
            next.sort_by_key(|&u| (degree(u), u));
            next.dedup();
            for u in next {
                placed[u] = true;
                order.push(u);
            }
        }
    }
    order.reverse();
    order
}

/// A node far from `seed` within its component: the last level of repeated breadth-first
/// searches, until the eccentricity stops growing.
fn peripheral(adjacent: &[Vec<usize>], seed: usize) -> usize {
    let mut start = seed;
    let mut depth = 0;
    loop {
        let (far, d) = farthest(adjacent, start);
        if d <= depth {
            return start;
        }
        depth = d;
        start = far;
    }
}

/// The farthest node from `start` (fewest neighbours among the farthest) and its distance.
fn farthest(adjacent: &[Vec<usize>], start: usize) -> (usize, usize) {
    let mut dist = vec![usize::MAX; adjacent.len()];
    dist[start] = 0;
    let mut queue = std::collections::VecDeque::from([start]);
    let mut best = (start, 0);
    while let Some(v) = queue.pop_front() {
        for &u in &adjacent[v] {
            if dist[u] == usize::MAX {
                dist[u] = dist[v] + 1;
                queue.push_back(u);
                let better = dist[u] > best.1 || (dist[u] == best.1 && adjacent[u].len() < adjacent[best.0].len());
                if better {
                    best = (u, dist[u]);
                }
            }
        }
    }
    best
}

/// Node adjacency of a mesh given as each element's node list.
pub fn adjacency<'a>(n_nodes: usize, elements: impl Iterator<Item = &'a [usize]>) -> Vec<Vec<usize>> {
    let mut adj = vec![Vec::new(); n_nodes];
    for nodes in elements {
        for &a in nodes {
            adj[a].extend(nodes.iter().copied().filter(|&b| b != a));
        }
    }
    for list in &mut adj {
        list.sort_unstable();
        list.dedup();
    }
    adj
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a long grid of quadrilaterals, RCM numbers across the short side: no element
    /// spans more than about two fronts of nodes (its fronts run diagonally), where the
    /// row-by-row order along the long side spans a whole long row.
    #[test]
    fn a_long_grid_is_numbered_across_its_short_side() {
        let (nx, ny) = (30usize, 4usize);
        let id = |i: usize, j: usize| i + j * (nx + 1);
        let elements: Vec<[usize; 4]> = (0..nx)
            .flat_map(|i| (0..ny).map(move |j| [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]))
            .collect();
        let n = (nx + 1) * (ny + 1);
        let order = reverse_cuthill_mckee(&adjacency(n, elements.iter().map(|e| &e[..])));
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "a permutation");
        let mut rank = vec![0; n];
        for (r, &v) in order.iter().enumerate() {
            rank[v] = r;
        }
        let span = |rank: &dyn Fn(usize) -> usize| {
            elements
                .iter()
                .map(|e| e.iter().map(|&v| rank(v)).max().unwrap() - e.iter().map(|&v| rank(v)).min().unwrap())
                .max()
                .unwrap()
        };
        let rcm = span(&|v| rank[v]);
        assert!(rcm <= 2 * (ny + 2), "RCM span {rcm}");
        assert!(span(&|v| v) > 2 * rcm, "natural span {} vs RCM {rcm}", span(&|v| v));
    }
}
