//! Islands: groups of dynamic bodies linked by contacts (thesis 6.1.3's
//! contact manager, Box2D's islands). An island sleeps and wakes as a whole:
//! a resting stack must not be half asleep.
//!
//! Built from scratch each step by union-find with path halving; static bodies
//! do not join islands (a floor would otherwise merge everything resting on it).
//! Deterministic: the representative of a set is its smallest body index.

/// Union-find over `n` elements.
#[derive(Debug, Clone)]
pub struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` singleton sets.
    pub fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n as u32).collect(),
        }
    }

    /// Representative of `x`'s set.
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.parent[x as usize] != x {
            let grand = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = grand;
            x = grand;
        }
        x
    }

    /// Merges the sets of `a` and `b`; the smaller representative wins.
    pub fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi as usize] = lo;
        }
    }
}

/// Island label per body: the smallest body index of its island, or
/// `u32::MAX` for bodies that are not dynamic (`dynamic[i] == false`).
pub fn label_islands(dynamic: &[bool], links: &[(u32, u32)]) -> Vec<u32> {
    let mut uf = UnionFind::new(dynamic.len());
    for &(a, b) in links {
        if dynamic[a as usize] && dynamic[b as usize] {
            uf.union(a, b);
        }
    }
    (0..dynamic.len() as u32)
        .map(|i| if dynamic[i as usize] { uf.find(i) } else { u32::MAX })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn static_bodies_do_not_merge_islands() {
        // 0 static floor; 1-2 stacked on it; 3 alone on it; 4-5 touching in the air.
        let dynamic = [false, true, true, true, true, true];
        let links = [(0, 1), (1, 2), (0, 3), (5, 4)];
        let labels = label_islands(&dynamic, &links);
        assert_eq!(labels, vec![u32::MAX, 1, 1, 3, 4, 4]);
    }

    #[test]
    fn chains_collapse_to_smallest_index() {
        let n = 100;
        let dynamic = vec![true; n];
        let links: Vec<(u32, u32)> = (1..n as u32).rev().map(|i| (i, i - 1)).collect();
        assert!(label_islands(&dynamic, &links).iter().all(|&l| l == 0));
    }
}
