//! The pool's ways of sharing work give the serial answer, in order, with
//! and without a crew, for any thread count, and never deadlock: not with
//! thousands of sections in a run, not with more threads than cores, not
//! with two runs on one shared pool at once, not with a run inside a run,
//! not when a member of a team panics (the panic reaches the caller).

use super::{runs_of, take_runs, BarrierState, Team, WorkerPool};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Sum of squares of each chunk, with the chunk's first index: what a
/// caller of `map_chunks` sees, cut in chunks of `chunk`.
fn chunk_sums(pool: &WorkerPool, items: &[u64], chunk: usize) -> Vec<(usize, u64)> {
    pool.map_chunks(items, chunk, |first, run| {
        (first, run.iter().map(|x| x * x).sum::<u64>())
    })
}

#[test]
fn map_chunks_in_a_run_keeps_every_chunk_in_its_place() {
    let items: Vec<u64> = (0..1000).collect();
    let total: u64 = items.iter().map(|x| x * x).sum();
    for threads in [1, 2, 3, 8] {
        let pool = WorkerPool::new(threads);
        for chunk in [1, 7, 64, 999, 1000, 5000] {
            let sums = pool.run(|crewed| chunk_sums(crewed, &items, chunk));
            let expected = if threads == 1 || chunk >= items.len() {
                vec![(0, total)]
            } else {
                (0..items.len())
                    .step_by(chunk)
                    .map(|s| {
                        (
                            s,
                            items[s..(s + chunk).min(items.len())].iter().map(|x| x * x).sum(),
                        )
                    })
                    .collect()
            };
            assert_eq!(sums, expected, "{threads} threads, chunks of {chunk}");
        }
    }
}

#[test]
fn for_each_mut_in_a_run_visits_every_item_once() {
    for threads in [1, 2, 4] {
        let pool = WorkerPool::new(threads);
        let mut items = vec![0u32; 257];
        pool.run(|crewed| {
            for _ in 0..3 {
                crewed.for_each_mut(&mut items, |k, item| *item += k as u32 + 1);
            }
        });
        let expected: Vec<u32> = (0..257).map(|k| 3 * (k + 1)).collect();
        assert_eq!(items, expected, "{threads} threads");
    }
}

#[test]
fn a_team_in_a_run_has_each_member_once_and_meets_at_barriers() {
    for threads in [2, 3, 8] {
        let pool = WorkerPool::new(threads);
        pool.run(|crewed| {
            for round in 0..50 {
                let seen = Mutex::new(Vec::new());
                let phase = AtomicUsize::new(0);
                let lead = crewed.team(|team: &Team| {
                    seen.lock().unwrap().push(team.index());
                    // Everyone arrives before anyone reads the count.
                    phase.fetch_add(1, Ordering::SeqCst);
                    team.barrier();
                    let arrived = phase.load(Ordering::SeqCst);
                    team.barrier();
                    (team.size(), arrived)
                });
                let mut seen = seen.into_inner().unwrap();
                seen.sort_unstable();
                let (size, arrived) = lead;
                assert_eq!(seen, (0..size).collect::<Vec<_>>(), "round {round}");
                assert_eq!(arrived, size, "round {round}: the barrier let one through early");
                assert!(size >= 1 && size <= threads as usize);
            }
        });
    }
}

#[test]
fn a_member_that_awaits_its_peers_sees_what_they_wrote_before_signalling() {
    // Each member writes its round, signals, awaits the others and reads
    // theirs: every other member must have reached the round (and what it
    // wrote before signalling must show). Members are held back unevenly,
    // so that each is sometimes ahead and sometimes behind.
    for threads in [2, 3, 8] {
        let pool = WorkerPool::new(threads);
        for crewed in [false, true] {
            let check = |pool: &WorkerPool| {
                let cells: Vec<AtomicUsize> = (0..threads).map(|_| AtomicUsize::new(0)).collect();
                let late = AtomicUsize::new(0);
                pool.team(|team: &Team| {
                    for round in 1..=200 {
                        if (round + team.index()).is_multiple_of(7) {
                            std::thread::sleep(std::time::Duration::from_micros(30));
                        }
                        cells[team.index()].store(round, Ordering::Relaxed);
                        team.signal();
                        team.await_peers();
                        assert!(team.peers_ready());
                        for cell in &cells[..team.size()] {
                            if cell.load(Ordering::Relaxed) < round {
                                late.fetch_add(1, Ordering::SeqCst);
                            }
                        }
                    }
                    team.barrier();
                });
                assert_eq!(
                    late.load(Ordering::SeqCst),
                    0,
                    "{threads} threads: a member went on early"
                );
            };
            if crewed {
                pool.run(|crewed| check(crewed));
            } else {
                check(&pool);
            }
        }
    }
}

#[test]
fn a_team_takes_every_slice_exactly_once_call_after_call() {
    // Slices of unequal cost (the first thread's own run is slow, so the
    // others take from its back), several calls between barriers as the
    // solver's passes make them, with and without a crew.
    for threads in [1, 2, 3, 8] {
        let pool = WorkerPool::new(threads);
        for crewed in [false, true] {
            let check = |pool: &WorkerPool| {
                for n in [0, 1, 2, 5, 64, 1000] {
                    let taken: Vec<AtomicUsize> = (0..n).map(|_| AtomicUsize::new(0)).collect();
                    let by = Mutex::new(vec![usize::MAX; n]);
                    pool.team(|team: &Team| {
                        for call in 0..4 {
                            team.slices(n, |k| {
                                taken[k].fetch_add(1, Ordering::SeqCst);
                                by.lock().unwrap()[k] = team.index();
                                if team.index() == 0 && call % 2 == 0 {
                                    std::thread::sleep(std::time::Duration::from_micros(20));
                                }
                            });
                            team.barrier();
                        }
                    });
                    for (k, t) in taken.iter().enumerate() {
                        assert_eq!(
                            t.load(Ordering::SeqCst),
                            4,
                            "{threads} threads, {n} slices: slice {k}"
                        );
                    }
                    assert!(by.into_inner().unwrap().iter().all(|&t| t < threads as usize));
                }
            };
            if crewed {
                pool.run(|c| check(c));
            } else {
                check(&pool);
            }
        }
    }
}

#[test]
fn runs_are_taken_own_first_then_from_the_others_backs_each_item_once() {
    // Alone (the other members never came): member 1 takes its own run
    // front to back, then the others' runs back to front.
    let runs = runs_of(10, 3);
    let mut order = Vec::new();
    take_runs(&runs, 1, |k| order.push(k));
    assert_eq!(order, [3, 4, 5, 9, 8, 7, 6, 2, 1, 0]);
    let mut again = Vec::new();
    take_runs(&runs, 0, |k| again.push(k));
    assert!(again.is_empty(), "every item was taken: {again:?}");
    // A member without a run of its own (a helper beyond the count the runs
    // were cut for) takes from the others' backs.
    let runs = runs_of(4, 2);
    let mut late = Vec::new();
    take_runs(&runs, 5, |k| late.push(k));
    assert_eq!(late, [1, 0, 3, 2]);
    // Members at once, some beyond the runs, unequal costs: each item once.
    for (n, members, threads) in [(0, 2, 3), (1, 2, 2), (1000, 2, 2), (1000, 3, 5), (37, 8, 3)] {
        let runs = runs_of(n, members);
        let taken: Vec<AtomicUsize> = (0..n).map(|_| AtomicUsize::new(0)).collect();
        std::thread::scope(|scope| {
            for me in 0..threads {
                let (runs, taken) = (&runs, &taken);
                scope.spawn(move || {
                    take_runs(runs, me, |k| {
                        taken[k].fetch_add(1, Ordering::SeqCst);
                        if me == 0 && k % 7 == 0 {
                            std::thread::sleep(std::time::Duration::from_micros(5));
                        }
                    })
                });
            }
        });
        for (k, t) in taken.iter().enumerate() {
            assert_eq!(
                t.load(Ordering::SeqCst),
                1,
                "{n} items, {members} runs, {threads} takers: item {k}"
            );
        }
    }
}

#[test]
fn a_run_takes_no_more_helpers_than_the_machine_has_cores() {
    // Eight threads asked for: the pool has eight, a run's teams at most
    // as many members as cores (a helper without a core spins on one that
    // another member needs), and the answer is the serial one.
    let pool = WorkerPool::new(8);
    assert_eq!(pool.threads(), 8);
    let items: Vec<u64> = (0..1000).collect();
    let (largest, sums) = pool.run(|crewed| {
        let largest = (0..200).map(|_| crewed.team(|team: &Team| team.size())).max();
        (largest.unwrap_or(0), chunk_sums(crewed, &items, 100))
    });
    assert!(
        (1..=super::cores()).contains(&largest),
        "a team of {largest} on {} cores",
        super::cores()
    );
    let expected: Vec<(usize, u64)> = (0..1000)
        .step_by(100)
        .map(|s| (s, items[s..s + 100].iter().map(|x| x * x).sum()))
        .collect();
    assert_eq!(sums, expected);
}

#[test]
fn thousands_of_sections_in_one_run_all_finish() {
    let pool = WorkerPool::new(2);
    let items: Vec<u64> = (0..64).collect();
    let done = pool.run(|crewed| {
        let mut done = 0;
        for _ in 0..5000 {
            done += chunk_sums(crewed, &items, 8).len();
        }
        done
    });
    assert_eq!(done, 5000 * 8);
}

#[test]
fn two_runs_on_one_shared_pool_at_once_both_finish_right() {
    let items: Vec<u64> = (0..500).collect();
    let serial = chunk_sums(&WorkerPool::serial(), &items, 10);
    let total = serial[0].1;
    std::thread::scope(|s| {
        let runs: Vec<_> = (0..2)
            .map(|_| {
                s.spawn(|| {
                    let pool = WorkerPool::new(2);
                    pool.run(|crewed| {
                        (0..200)
                            .map(|_| chunk_sums(crewed, &items, 10).iter().map(|c| c.1).sum::<u64>())
                            .collect::<Vec<_>>()
                    })
                })
            })
            .collect();
        for run in runs {
            assert!(run.join().unwrap().iter().all(|&t| t == total));
        }
    });
}

#[test]
fn a_run_inside_a_run_runs_on_the_same_crew() {
    let pool = WorkerPool::new(2);
    let items: Vec<u64> = (0..100).collect();
    let sums = pool.run(|outer| outer.run(|inner| chunk_sums(inner, &items, 10)));
    assert_eq!(sums.len(), 10);
    assert_eq!(
        sums.iter().map(|c| c.1).sum::<u64>(),
        items.iter().map(|x| x * x).sum::<u64>()
    );
}

/// Runs `job` on a thread of its own and says whether it panicked, failing
/// the test if it has not finished within a minute (a hang).
fn fails_in_time(job: impl FnOnce() + Send + 'static) -> bool {
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(job));
        let _ = tx.send(outcome.is_err());
    });
    rx.recv_timeout(std::time::Duration::from_secs(60))
        .expect("the team hung after a member panicked")
}

/// A team of two in which member `panicking` panics while the other
/// waits for it in `wait`.
fn team_with_a_panic(team: &Team, panicking: usize, wait: fn(&Team)) {
    assert_eq!(team.size(), 2, "a team of two");
    if team.index() == panicking {
        panic!("member {} fails on purpose", team.index());
    }
    wait(team);
}

/// Two barriers.
fn at_barriers(team: &Team) {
    team.barrier();
    team.barrier();
}

/// A signal, then a wait for the other's.
fn at_a_signal(team: &Team) {
    team.signal();
    team.await_peers();
}

#[test]
fn a_member_that_panics_fails_the_team_instead_of_hanging_it() {
    for panicking in [0usize, 1] {
        // A team of the pool's threads, at a barrier and at a signal.
        let failed = fails_in_time(move || {
            WorkerPool::new(2).team(|team| team_with_a_panic(team, panicking, at_barriers))
        });
        assert!(failed, "member {panicking}'s panic did not reach the caller");
        let failed = fails_in_time(move || {
            WorkerPool::new(2).team(|team| team_with_a_panic(team, panicking, at_a_signal))
        });
        assert!(
            failed,
            "member {panicking}'s panic did not reach the awaiting member"
        );
        // A team of a run's crew (a helper needs a second core).
        if super::cores() < 2 {
            continue;
        }
        let failed = fails_in_time(move || {
            WorkerPool::new(2).run(|crewed| {
                let crew = crewed.crew.as_ref().expect("a run has a crew");
                let start = std::time::Instant::now();
                while crew.joined() == 0 && start.elapsed().as_secs() < 10 {
                    std::thread::yield_now();
                }
                crewed.team(|team| team_with_a_panic(team, panicking, at_barriers))
            })
        });
        assert!(
            failed,
            "member {panicking}'s panic did not reach the caller of the run"
        );
    }
}

#[test]
fn blocks_give_each_thread_one_run_of_whole_blocks_covering_every_item_once() {
    for size in 1..=5usize {
        for n in [0usize, 1, 63, 64, 127, 128, 129, 1000, 1025] {
            let mut seen = vec![0u32; n];
            let mut previous_end = 0;
            for index in 0..size {
                let team = Team {
                    size,
                    index,
                    sync: Arc::new(BarrierState::new(size)),
                };
                let ranges: Vec<_> = Team::blocks_of(team.block_run(n, 64), 64).collect();
                for (k, r) in ranges.iter().enumerate() {
                    // Whole blocks (only the last one of all may be short),
                    // each run contiguous and after the previous thread's.
                    assert_eq!(r.start % 64, 0, "n {n}, size {size}, thread {index}");
                    assert!(r.len() == 64 || r.end == n, "n {n}, size {size}: {r:?}");
                    if k == 0 {
                        assert_eq!(r.start, previous_end, "n {n}, size {size}, thread {index}");
                    } else {
                        assert_eq!(r.start, ranges[k - 1].end);
                    }
                    seen[r.clone()].iter_mut().for_each(|s| *s += 1);
                }
                if let Some(last) = ranges.last() {
                    previous_end = last.end;
                }
                // The runs differ by at most one block.
                let blocks = n.div_ceil(64);
                if n >= 128 && size > 1 {
                    assert!(ranges.len() >= blocks / size && ranges.len() <= blocks.div_ceil(size));
                }
            }
            assert!(seen.iter().all(|&s| s == 1), "n {n}, size {size}: {seen:?}");
        }
    }
}
