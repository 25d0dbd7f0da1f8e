//! Whose turn it is to render, across all of a server's sessions.
//!
//! Every render of a session (a preview, a pass, the denoiser's guides) takes a
//! turn here; one runs at a time, its rows spread over every core by rayon. A
//! turn for a new camera's first frame goes before any turn that refines a picture
//! already shown, and turns of the same kind go in the order asked, so each page
//! refines in its turn. Without this, twenty pages' passes queue in rayon in the
//! order they started, and a new camera's first frame waits behind all of them;
//! with it, it waits for the pass running and the other new cameras' first frames.

use std::collections::VecDeque;
use std::sync::{Condvar, Mutex, MutexGuard};

/// The queue of renders waiting, and whether one runs.
#[derive(Default)]
pub struct Turns {
    state: Mutex<State>,
    changed: Condvar,
}

#[derive(Default)]
struct State {
    /// True while a turn is taken.
    busy: bool,
    /// Tickets of first frames waiting, oldest first.
    first: VecDeque<u64>,
    /// Tickets of refining renders waiting, oldest first.
    refine: VecDeque<u64>,
    /// The next ticket's number.
    next: u64,
}

impl State {
    /// The ticket whose turn is next.
    fn head(&self) -> Option<u64> {
        self.first.front().or(self.refine.front()).copied()
    }

    fn forget(&mut self, ticket: u64) {
        self.first.retain(|&t| t != ticket);
        self.refine.retain(|&t| t != ticket);
    }
}

/// A turn taken: the next one starts when it is dropped.
pub struct Turn<'a>(&'a Turns);

impl Drop for Turn<'_> {
    fn drop(&mut self) {
        self.0.lock().busy = false;
        self.0.changed.notify_all();
    }
}

impl Turns {
    /// Waits for a turn, for a first frame if `first`; `None` as soon as `give_up`
    /// says so (a newer request replaced this one), checked whenever
    /// [`Turns::wake`] is called or a turn ends.
    pub fn take(&self, first: bool, give_up: impl Fn() -> bool) -> Option<Turn<'_>> {
        let mut state = self.lock();
        let ticket = state.next;
        state.next += 1;
        if first {
            state.first.push_back(ticket);
        } else {
            state.refine.push_back(ticket);
        }
        loop {
            if give_up() {
                state.forget(ticket);
                drop(state);
                // The head of the queue may have changed.
                self.changed.notify_all();
                return None;
            }
            if !state.busy && state.head() == Some(ticket) {
                state.forget(ticket);
                state.busy = true;
                return Some(Turn(self));
            }
            state = match self.changed.wait(state) {
                Ok(s) => s,
                Err(poisoned) => poisoned.into_inner(),
            };
        }
    }

    /// Wakes the waiting renders to check whether they are still wanted.
    pub fn wake(&self) {
        let _state = self.lock();
        self.changed.notify_all();
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // The state is a queue of numbers: a panic while it was held leaves it
        // usable.
        self.state.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::Duration;

    /// Starts a thread that waits for a turn and then records `name`; returns once
    /// it is queued (it holds the ticket before `turns.next`).
    fn waiter(
        turns: &Arc<Turns>,
        order: &Arc<Mutex<Vec<&'static str>>>,
        name: &'static str,
        first: bool,
        give_up: Arc<AtomicBool>,
    ) -> std::thread::JoinHandle<bool> {
        let ticket = turns.lock().next;
        let (turns, order) = (turns.clone(), order.clone());
        let queued = turns.clone();
        let handle = std::thread::spawn(move || {
            let turn = turns.take(first, || give_up.load(Ordering::SeqCst));
            if turn.is_some() {
                order.lock().unwrap().push(name);
            }
            turn.is_some()
        });
        while queued.lock().next <= ticket {
            std::thread::sleep(Duration::from_millis(1));
        }
        handle
    }

    #[test]
    fn first_frames_go_before_refining_and_each_kind_in_order() {
        let turns = Arc::new(Turns::default());
        let order = Arc::new(Mutex::new(Vec::new()));
        let never = || Arc::new(AtomicBool::new(false));
        let running = turns.take(false, || false).expect("a free turn");
        let waiters = [
            waiter(&turns, &order, "refine a", false, never()),
            waiter(&turns, &order, "first b", true, never()),
            waiter(&turns, &order, "refine c", false, never()),
            waiter(&turns, &order, "first d", true, never()),
        ];
        drop(running);
        assert!(waiters.into_iter().all(|w| w.join().unwrap()));
        assert_eq!(
            *order.lock().unwrap(),
            ["first b", "first d", "refine a", "refine c"]
        );
    }

    #[test]
    fn a_replaced_render_leaves_the_queue_when_woken() {
        let turns = Arc::new(Turns::default());
        let order = Arc::new(Mutex::new(Vec::new()));
        let running = turns.take(true, || false).expect("a free turn");
        let replaced = Arc::new(AtomicBool::new(false));
        let gone = waiter(&turns, &order, "replaced", true, replaced.clone());
        let stays = waiter(&turns, &order, "stays", false, Arc::new(AtomicBool::new(false)));
        replaced.store(true, Ordering::SeqCst);
        turns.wake();
        assert!(!gone.join().unwrap(), "a replaced render gives up its place");
        drop(running);
        assert!(stays.join().unwrap());
        assert_eq!(*order.lock().unwrap(), ["stays"]);
    }
}
