//! Arc identities of carrier phases: one ambiguity per arc, a new arc at every slip or loss of lock.
//!
//! A receiver's phase of (satellite, slot) starts a new arc at an epoch when any of these holds:
//! - it had no phase at the previous epoch the engine processed (a gap in the data, or the first epoch);
//! - the session itself has a gap: more than [`MAX_GAP_INTERVALS`] times the shortest interval between
//!   epochs seen so far since the previous epoch (the jump tests below allow for the ionosphere's change
//!   over the interval, which over a long gap leaves them blind to slips of metres);
//! - the RINEX loss-of-lock indicator has bit 0 set;
//! - phase minus code (both in metres) jumped by more than [`PHASE_CODE_JUMP_M`] +
//!   [`PHASE_CODE_RATE_M_S`] x the time since the previous epoch: catches slips of tens of cycles that
//!   a geometry-free test misses when one slot alone is tracked;
//! - the geometry-free combination `lambda_0 phi_0 - lambda_j phi_j` (slot 0 and the lowest other slot
//!   with phase at both epochs) jumped by more than [`GEOMETRY_FREE_JUMP_M`] +
//!   [`GEOMETRY_FREE_RATE_M_S`] x the time since the previous epoch (RTKLIB's `thresslip` of 5 cm, widened
//!   for the ionosphere's change over long intervals); every slot of the satellite starts a new arc.
//!
//! The pair (reference antenna, rover) of each (satellite, slot) gets a new arc identity whenever either
//! receiver starts a new arc; identities are handed out in order, so that the same observations give the
//! same identities however they are split into chunks.

use crate::gnss::observations::Observations;
use crate::gnss::signal::MAX_FREQUENCIES;

/// Phase-minus-code jump that always counts as a slip, m. Code noise with multipath stays within a few
/// metres between consecutive epochs; 5 m is 26 cycles of L1.
pub const PHASE_CODE_JUMP_M: f64 = 5.0;
/// Allowance for the ionosphere's code-phase divergence (twice its delay rate), m/s.
pub const PHASE_CODE_RATE_M_S: f64 = 0.1;
/// Geometry-free jump that counts as a slip, m (RTKLIB's default `thresslip`).
pub const GEOMETRY_FREE_JUMP_M: f64 = 0.05;
/// Allowance for the ionosphere's change of the geometry-free combination, m/s.
pub const GEOMETRY_FREE_RATE_M_S: f64 = 0.004;

/// Longest time between epochs, in shortest intervals seen, over which arcs continue (RTKLIB's
/// `maxout` of 5 epochs for an outage).
pub const MAX_GAP_INTERVALS: f64 = 5.0;

/// Arc state of every receiver and every (rover, satellite, slot) pair.
#[derive(Debug, Clone)]
pub(crate) struct ArcTracker {
    n_sats: usize,
    n_receivers: usize,
    /// Per (receiver, satellite, slot): whether it had phase at the previous epoch, and its phase
    /// minus code, m, when it had code too.
    phase_seen: Vec<bool>,
    phase_minus_code_m: Vec<Option<f64>>,
    /// Per (receiver, satellite): slot paired with slot 0 and the geometry-free value, m.
    geometry_free: Vec<Option<(usize, f64)>>,
    /// Per (rover - 1, satellite, slot): the pair's arc identity.
    pair_arc: Vec<u64>,
    next_arc: u64,
    previous_time_ns: Option<i64>,
    /// Shortest positive time between consecutive epochs so far, s.
    interval_s: f64,
}

impl ArcTracker {
    pub(crate) fn new(n_sats: usize, n_receivers: usize) -> Self {
        let cells = n_receivers * n_sats * MAX_FREQUENCIES;
        ArcTracker {
            n_sats,
            n_receivers,
            phase_seen: vec![false; cells],
            phase_minus_code_m: vec![None; cells],
            geometry_free: vec![None; n_receivers * n_sats],
            pair_arc: vec![0; n_receivers.saturating_sub(1) * n_sats * MAX_FREQUENCIES],
            next_arc: 0,
            previous_time_ns: None,
            interval_s: f64::INFINITY,
        }
    }

    fn cell(&self, receiver: usize, sat: usize, slot: usize) -> usize {
        (receiver * self.n_sats + sat) * MAX_FREQUENCIES + slot
    }

    /// Advances to `epoch` of `obs` (the next epoch in time) and returns, per receiver x satellite x
    /// slot, whether that phase starts a new arc there.
    fn slips(&mut self, obs: &Observations, epoch: usize) -> Vec<bool> {
        let dt_s = self
            .previous_time_ns
            .map_or(0.0, |t| (obs.time_gpst_ns[epoch] - t) as f64 * 1e-9);
        let gap = dt_s > MAX_GAP_INTERVALS * self.interval_s;
        if dt_s > 0.0 {
            self.interval_s = self.interval_s.min(dt_s);
        }
        let mut slipped = vec![false; self.phase_seen.len()];
        for r in 0..self.n_receivers {
            let rx = &obs.receivers[r];
            for s in 0..self.n_sats {
                let metres = |slot: usize| {
                    let i = obs.index(epoch, s, slot);
                    let f = obs.frequency_hz(s, slot)?;
                    let phi = rx.phase_cycles[i];
                    phi.is_finite()
                        .then_some(phi * crate::gnss::signal::SPEED_OF_LIGHT_M_S / f)
                };
                for slot in 0..MAX_FREQUENCIES {
                    let c = self.cell(r, s, slot);
                    let i = obs.index(epoch, s, slot);
                    let Some(phase_m) = metres(slot) else {
                        self.phase_seen[c] = false;
                        self.phase_minus_code_m[c] = None;
                        continue;
                    };
                    let code = rx.code_m[i];
                    let pc = code.is_finite().then_some(phase_m - code);
                    let jumped = match (self.phase_minus_code_m[c], pc) {
                        (Some(a), Some(b)) => {
                            (b - a).abs() > PHASE_CODE_JUMP_M + PHASE_CODE_RATE_M_S * dt_s
                        }
                        _ => false,
                    };
                    slipped[c] = !self.phase_seen[c] || gap || rx.lli[i] & 1 != 0 || jumped;
                    self.phase_seen[c] = true;
                    if pc.is_some() {
                        self.phase_minus_code_m[c] = pc;
                    }
                }
                let g = r * self.n_sats + s;
                let now = metres(0).and_then(|p0| {
                    (1..MAX_FREQUENCIES).find_map(|j| metres(j).map(|pj| (j, p0 - pj)))
                });
                if let (Some((j0, a)), Some((j1, b))) = (self.geometry_free[g], now) {
                    if j0 == j1
                        && (b - a).abs() > GEOMETRY_FREE_JUMP_M + GEOMETRY_FREE_RATE_M_S * dt_s
                    {
                        for slot in 0..MAX_FREQUENCIES {
                            let c = self.cell(r, s, slot);
                            slipped[c] |= self.phase_seen[c];
                        }
                    }
                }
                self.geometry_free[g] = now;
            }
        }
        self.previous_time_ns = Some(obs.time_gpst_ns[epoch]);
        slipped
    }

    /// Advances to `epoch` and gives every (rover, satellite, slot) with a new arc at either receiver a
    /// new identity. Call once per epoch, in time order.
    pub(crate) fn advance(&mut self, obs: &Observations, epoch: usize) {
        let slipped = self.slips(obs, epoch);
        for rover in 1..self.n_receivers {
            for s in 0..self.n_sats {
                for slot in 0..MAX_FREQUENCIES {
                    let (b, r) = (self.cell(0, s, slot), self.cell(rover, s, slot));
                    if slipped[b] || slipped[r] {
                        let p = ((rover - 1) * self.n_sats + s) * MAX_FREQUENCIES + slot;
                        self.pair_arc[p] = self.next_arc;
                        self.next_arc += 1;
                    }
                }
            }
        }
    }

    /// Arc identity of (rover, satellite, slot) at the epoch last passed to [`ArcTracker::advance`]
    /// (meaningful where both receivers have phase there).
    pub(crate) fn arc(&self, rover: usize, sat: usize, slot: usize) -> u64 {
        self.pair_arc[((rover - 1) * self.n_sats + sat) * MAX_FREQUENCIES + slot]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gnss::observations::ReceiverObservations;
    use crate::gnss::signal::{carrier_frequency_hz, SatId, System, SPEED_OF_LIGHT_M_S};

    /// One GPS satellite, two receivers, `n` epochs 1 s apart; L1 and L2 phase equal to the code
    /// (no ionosphere) on a range that grows 500 m/s.
    fn session(n: usize) -> Observations {
        let cells = n * MAX_FREQUENCIES;
        let mut rx = ReceiverObservations {
            code_m: vec![f64::NAN; cells],
            phase_cycles: vec![f64::NAN; cells],
            doppler_hz: vec![f64::NAN; cells],
            snr_dbhz: vec![f64::NAN; cells],
            lli: vec![0; cells],
            approx_position_m: None,
        };
        for k in 0..n {
            let range = 2.2e7 + 500.0 * k as f64;
            for slot in 0..2 {
                let f = carrier_frequency_hz(System::Gps, slot, None).unwrap();
                rx.code_m[k * MAX_FREQUENCIES + slot] = range;
                rx.phase_cycles[k * MAX_FREQUENCIES + slot] = range * f / SPEED_OF_LIGHT_M_S;
            }
        }
        Observations {
            time_gpst_ns: (0..n as i64).map(|k| k * 1_000_000_000).collect(),
            sats: vec![SatId {
                system: System::Gps,
                prn: 1,
            }],
            glonass_channel: vec![None],
            receivers: vec![rx.clone(), rx],
        }
    }

    fn arcs(obs: &Observations) -> Vec<[u64; 2]> {
        let mut t = ArcTracker::new(1, 2);
        (0..obs.n_epochs())
            .map(|k| {
                t.advance(obs, k);
                [t.arc(1, 0, 0), t.arc(1, 0, 1)]
            })
            .collect()
    }

    /// Epochs (after the first) at which slot `slot` got a new identity.
    fn breaks(a: &[[u64; 2]], slot: usize) -> Vec<usize> {
        (1..a.len())
            .filter(|&k| a[k][slot] != a[k - 1][slot])
            .collect()
    }

    #[test]
    fn clean_phases_keep_one_arc_per_slot() {
        let a = arcs(&session(6));
        assert_eq!(breaks(&a, 0), Vec::<usize>::new());
        assert_eq!(breaks(&a, 1), Vec::<usize>::new());
        assert_ne!(a[0][0], a[0][1]);
    }

    #[test]
    fn loss_of_lock_at_the_rover_breaks_that_slot_only() {
        let mut obs = session(6);
        obs.receivers[1].lli[3 * MAX_FREQUENCIES + 1] = 1;
        let a = arcs(&obs);
        assert_eq!(breaks(&a, 1), vec![3]);
        assert_eq!(breaks(&a, 0), Vec::<usize>::new());
    }

    #[test]
    fn a_gap_at_the_base_starts_a_new_arc_when_the_phase_returns() {
        let mut obs = session(6);
        obs.receivers[0].phase_cycles[2 * MAX_FREQUENCIES] = f64::NAN;
        assert_eq!(breaks(&arcs(&obs), 0), vec![3]);
    }

    #[test]
    fn a_one_cycle_slip_on_one_slot_is_seen_by_the_geometry_free_test() {
        // 1 L2 cycle = 0.244 m of geometry-free jump (> 0.05 m), far below the phase-code threshold.
        let mut obs = session(6);
        for k in 4..6 {
            obs.receivers[1].phase_cycles[k * MAX_FREQUENCIES + 1] += 1.0;
        }
        let a = arcs(&obs);
        assert_eq!(breaks(&a, 0), vec![4]);
        assert_eq!(breaks(&a, 1), vec![4]);
    }

    #[test]
    fn a_large_slip_with_one_slot_is_seen_by_the_phase_code_test_and_small_noise_is_not() {
        let mut obs = session(6);
        for k in 0..6 {
            obs.receivers[1].phase_cycles[k * MAX_FREQUENCIES + 1] = f64::NAN;
            // 1 m of code noise (alternating) stays under the 5 m threshold.
            obs.receivers[1].code_m[k * MAX_FREQUENCIES] += if k % 2 == 0 { 1.0 } else { -1.0 };
        }
        for k in 3..6 {
            obs.receivers[1].phase_cycles[k * MAX_FREQUENCIES] += 40.0; // 7.6 m
        }
        assert_eq!(breaks(&arcs(&obs), 0), vec![3]);
    }

    #[test]
    fn a_gap_in_the_session_starts_new_arcs_and_a_short_one_does_not() {
        // Epochs 1 s apart, then 5 s (5 intervals: arcs go on), then 6 s more (over 5: new arcs).
        let mut obs = session(4);
        obs.time_gpst_ns = vec![0, 1_000_000_000, 6_000_000_000, 12_000_000_000];
        let a = arcs(&obs);
        assert_eq!(breaks(&a, 0), vec![3]);
        assert_eq!(breaks(&a, 1), vec![3]);
    }
}
