//! Splitting a plan into shards that balance estimated cost (for `--shard K/N`).

use crate::output::ShardSpec;
use crate::study::Plan;

/// Plan indices of the runs of each of `count` shards (ascending within a shard).
///
/// Greedy longest-processing-time assignment: runs sorted by estimated cost (largest first, then by
/// index) each go to the shard with the smallest load so far (the lowest-numbered one on ties).
/// Deterministic: the same plan and count always give the same split.
pub fn assign(costs: &[f64], count: usize) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..costs.len()).collect();
    let cost = |i: usize| if costs[i].is_finite() { costs[i].max(0.0) } else { 0.0 };
    order.sort_by(|&a, &b| cost(b).total_cmp(&cost(a)).then(a.cmp(&b)));
    let mut loads = vec![0.0_f64; count];
    let mut shards = vec![Vec::new(); count];
    for i in order {
        let lightest = (0..count).min_by(|&a, &b| loads[a].total_cmp(&loads[b]).then(a.cmp(&b))).unwrap_or(0);
        loads[lightest] += cost(i);
        shards[lightest].push(i);
    }
    for shard in &mut shards {
        shard.sort_unstable();
    }
    shards
}

/// Plan indices of the runs of one shard.
pub fn select(plan: &Plan, spec: ShardSpec) -> Vec<usize> {
    let costs: Vec<f64> = plan.runs.iter().map(|r| r.estimated_cost).collect();
    assign(&costs, spec.count).swap_remove(spec.index - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_run_lands_in_exactly_one_shard() {
        let costs: Vec<f64> = (0..23).map(|i| ((i * 7) % 5) as f64 + 1.0).collect();
        let shards = assign(&costs, 4);
        let mut all: Vec<usize> = shards.concat();
        all.sort_unstable();
        assert_eq!(all, (0..23).collect::<Vec<_>>());
    }

    #[test]
    fn loads_are_balanced_by_cost() {
        // One expensive run and many cheap ones: the expensive run gets a shard nearly to itself.
        let mut costs = vec![10.0];
        costs.extend(std::iter::repeat_n(1.0, 20));
        let shards = assign(&costs, 3);
        let loads: Vec<f64> = shards.iter().map(|s| s.iter().map(|&i| costs[i]).sum()).collect();
        assert_eq!(shards[0], vec![0], "the largest run goes first to shard 1");
        assert_eq!(loads, vec![10.0, 10.0, 10.0]);
    }

    #[test]
    fn more_shards_than_runs_leaves_some_empty() {
        let shards = assign(&[1.0, 2.0], 3);
        assert_eq!(shards, vec![vec![1], vec![0], vec![]]);
    }
}
