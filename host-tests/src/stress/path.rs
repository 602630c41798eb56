//! Path-state edges: path length and cone width across many bounces,
//! grazing incidence, ray-stack overflow.

use raymip::lod::table_lod;
use raymip::path::raystack::{DEFAULT_CAPACITY, PathState, RayStack};
use raymip::units::{Accurate, Log2Pb, PathLength, Spread, Width};

use super::lod::lod_ref;
use super::setup::spread;
use super::{Runner, bad, clamp, err};

pub(super) fn path(r: &mut Runner) {
    r.case(
        "Pl at the top of its range, 12 bounces",
        "ray stack: PathState::advance/bounce",
        || {
            let mut s = PathState::primary(&spread(), 0xA5);
            for _ in 0..12 {
                s = s.advance(PathLength::MAX).bounce(Spread::from_num(0.5));
            }
            let l = table_lod::<Accurate>(s.pl, Log2Pb::MIN).ok_or("untextured")?;
            let want = lod_ref(32.0 + 64.0);
            let ok = s.pl == PathLength::MAX
                && s.saturated
                && s.depth == 12
                && s.mask == 0xA5
                && s.cone.width == Width::MAX
                && (l.to_num::<f64>() - want).abs() <= 2.0 / 256.0;
            if ok {
                clamp(format!("Pl = MAX, w = MAX, saturated, lod {l}"))
            } else {
                bad(format!("{s:?}, lod {l}"))
            }
        },
    );
    r.case("spread ±MAX twice", "ray stack: PathState::bounce", || {
        let s = PathState::primary(&spread(), 1);
        let up = s.bounce(Spread::MAX).bounce(Spread::MAX);
        let down = s.bounce(Spread::MIN).bounce(Spread::MIN);
        if up.cone.spread == Spread::MAX
            && down.cone.spread == Spread::MIN
            && up.saturated
            && down.saturated
        {
            clamp("spread saturated at ±2, flagged")
        } else {
            bad(format!("{up:?} {down:?}"))
        }
    });
    r.case("depth 300 bounces", "ray stack: PathState::bounce", || {
        let s = (0..300).fold(PathState::default(), |p, _| p.bounce(Spread::ZERO));
        if s.depth == 255 {
            clamp("depth 255")
        } else {
            bad(format!("depth {}", s.depth))
        }
    });
    r.case(
        format!("push {} onto {DEFAULT_CAPACITY}", DEFAULT_CAPACITY + 1),
        "ray stack: RayStack::push",
        || {
            let mut st: RayStack = RayStack::new();
            let base = PathState::primary(&spread(), 0);
            for d in 0..DEFAULT_CAPACITY as u8 {
                st.push(PathState { depth: d, ..base })
                    .map_err(|e| e.to_string())?;
            }
            let extra = PathState { depth: 99, ..base };
            let res = st.push(extra);
            let order: Vec<u8> = std::iter::from_fn(|| st.pop()).map(|s| s.depth).collect();
            let want: Vec<u8> = (0..DEFAULT_CAPACITY as u8).rev().collect();
            match res {
                Err(e) if e.0 == extra && order == want => {
                    err("StackFull with the state handed back; 10 entries kept, LIFO")
                }
                o => bad(format!("{o:?}, popped {order:?}")),
            }
        },
    );
    r.case("pop an empty stack", "ray stack: RayStack::pop", || {
        let mut st: RayStack = RayStack::new();
        match st.pop() {
            None => err("None"),
            o => bad(format!("{o:?}")),
        }
    });
}
