//! Every traversal mode on one field, asserting bit-identical answers.
//!
//! `Modes::new(&field)` builds skip grids of several layouts (2-, 4- and
//! 8-cell blocks, one level and full pyramids); every query runs the flat
//! walk and each (layout, mode) pair and panics unless all agree to the
//! bit. The flat answer is returned, so a suite written against the flat
//! walk (oracle, hard cases, cracks) checks every mode at once.

use hfray::packet::{RayPacket, LANES};
use hfray::traversal::GridHit;
use hfray::{Counters, FieldHit, HeightField, Ray, Real, SkipGrid, SkipLayout, Traversal};

/// Runs `f` at the x87 precision the i486 firmware renders at (the
/// firmware README's "Numeric identity"): x87 registers round each
/// operation to the control word's precision, not to the operand's type,
/// so on x87 targets (i586, no SSE) the walks run here with it set to the
/// sample type's significand (24 bits for `f32`, 53 for `f64`), and back
/// to Linux's default (64) after. Elsewhere `f` just runs.
#[cfg(all(target_arch = "x86", not(target_feature = "sse2")))]
pub fn at_precision<R>(significand_bits: u32, f: impl FnOnce() -> R) -> R {
    fn set(precision_control: u16) {
        let cw: u16 = 0x007F | (precision_control << 8);
        // SAFETY: loads the x87 control word from a live local, nothing
        // else. Not `nomem`: a barrier for the memory accesses around it.
        unsafe { std::arch::asm!("fldcw [{}]", in(reg) &cw, options(nostack)) };
    }
    set(match significand_bits {
        0..=24 => 0b00,
        25..=53 => 0b10,
        _ => 0b11,
    });
    let r = std::hint::black_box(f());
    set(0b11);
    r
}

#[cfg(not(all(target_arch = "x86", not(target_feature = "sse2"))))]
pub fn at_precision<R>(_significand_bits: u32, f: impl FnOnce() -> R) -> R {
    f()
}

/// The significand of `S` for [`at_precision`] (fixed point: integer
/// arithmetic, any).
fn significand_bits<S: Real>() -> u32 {
    if std::any::type_name::<S>() == "f64" {
        53
    } else {
        24
    }
}

pub struct Modes {
    grids: Vec<(SkipLayout, Vec<u8>)>,
    /// Queries answered (each by every mode).
    pub queries: u64,
    /// Packet runs (one mode, one packet) whose lanes tested another number
    /// of blocks than their rays' own walks: the packet started them past
    /// blocks culled for all of them.
    pub shared_starts: u64,
    /// Block tests the packets saved, in all.
    pub blocks_saved: i64,
}

/// Layouts checked: one level of small blocks (many jumps, many block
/// edges) and pyramids of fan-out 2, 4 and 8.
pub fn layouts(width: u32, depth: u32) -> Vec<SkipLayout> {
    vec![
        SkipLayout::blocks(1),
        SkipLayout::blocks(2),
        SkipLayout::pyramid(width, depth, 1),
        SkipLayout::pyramid(width, depth, 2),
        SkipLayout::pyramid(width, depth, 3),
    ]
}

fn same_grid_hit<S: Real>(a: &Option<GridHit<S>>, b: &Option<GridHit<S>>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.t.to_f64().to_bits() == b.t.to_f64().to_bits()
                && a.cell_x == b.cell_x
                && a.cell_z == b.cell_z
                && a.triangle == b.triangle
                && a.local.0.to_f64().to_bits() == b.local.0.to_f64().to_bits()
                && a.local.1.to_f64().to_bits() == b.local.1.to_f64().to_bits()
        }
        _ => false,
    }
}

impl Modes {
    pub fn new(field: &HeightField<'_>) -> Self {
        let mut grids = Vec::new();
        for layout in layouts(field.width(), field.depth()) {
            let n = SkipGrid::bytes_needed_for(field, layout).unwrap();
            let mut buf = vec![0u8; n];
            SkipGrid::build(field, layout, &mut buf).unwrap();
            grids.push((layout, buf));
        }
        Modes {
            grids,
            queries: 0,
            shared_starts: 0,
            blocks_saved: 0,
        }
    }

    /// Calls `f` with the field in every (layout, mode) other than flat.
    fn each<'f, R>(
        &self,
        field: &HeightField<'f>,
        mut f: impl FnMut(&HeightField<'_>, String) -> R,
    ) -> Vec<(String, R)> {
        let mut out = Vec::new();
        for (layout, buf) in &self.grids {
            for mode in [Traversal::Blocks, Traversal::Hierarchy] {
                let g = field.clone().with_skip(buf).unwrap().with_traversal(mode);
                let name = format!("{mode:?} {layout:?}");
                let r = f(&g, name.clone());
                out.push((name, r));
            }
        }
        out
    }

    /// `intersect_in::<S>` in every mode; panics on any disagreement.
    pub fn intersect_in<S: Real>(
        &mut self,
        field: &HeightField<'_>,
        o: [S; 3],
        d: [S; 3],
        t_min: S,
        t_max: S,
        counters: &mut Counters,
    ) -> Option<GridHit<S>> {
        self.queries += 1;
        let flat = field.clone().with_traversal(Traversal::Flat);
        let bits = significand_bits::<S>();
        let reference = at_precision(bits, || {
            flat.intersect_in::<S>(o, d, t_min, t_max, counters)
        });
        for (name, r) in self.each(field, |g, _| {
            at_precision(bits, || {
                g.intersect_in::<S>(o, d, t_min, t_max, &mut Counters::default())
            })
        }) {
            assert!(
                same_grid_hit(&reference, &r),
                "mode {name} differs from the flat walk: {r:?} vs {reference:?} \
                 (o={o:?} d={d:?} t=[{t_min:?},{t_max:?}] field {}x{})",
                field.width(),
                field.depth()
            );
        }
        reference
    }

    /// `intersect_packet` and `intersect_t_packet` in the flat walk and
    /// every mode; panics unless each lane is, bit for bit, [`Self::intersect`]
    /// of its ray (which checks the modes against the flat walk), and the
    /// packet visited the same cells.
    pub fn intersect_packet(
        &mut self,
        field: &HeightField<'_>,
        rays: &[Ray; LANES],
        t_min: f32,
        t_max: f32,
    ) -> [Option<FieldHit>; LANES] {
        let reference: [Option<FieldHit>; LANES] =
            std::array::from_fn(|l| self.intersect(field, &rays[l], t_min, t_max));
        let packet = RayPacket::from_rays(rays);
        let flat = field.clone().with_traversal(Traversal::Flat);
        let mut runs = vec![(
            "Flat".to_string(),
            at_precision(24, || packet_hits(&flat, &packet, t_min, t_max)),
        )];
        runs.extend(self.each(field, |g, _| {
            at_precision(24, || packet_hits(g, &packet, t_min, t_max))
        }));
        for (name, (hits, ts, counters, alone)) in runs {
            for l in 0..LANES {
                assert!(
                    same_field_hit(&reference[l], &hits[l])
                        && ts[l].map(f32::to_bits) == reference[l].map(|h| h.t.to_bits()),
                    "packet lane {l} in mode {name} differs from the ray's own walk: \
                     {:?} vs {:?} (ray {:?} t=[{t_min},{t_max}] field {}x{})",
                    hits[l],
                    reference[l],
                    rays[l],
                    field.width(),
                    field.depth()
                );
            }
            // The lanes visit the cells their own walks visit; a shared start
            // changes only the block tests (usually fewer). Not on the x87
            // for a packet with a subnormal direction component (see
            // `x87_subnormal_direction`): the hits are checked above.
            let visits = |c: &Counters| (c.cells, c.triangle_tests, c.resumed);
            if !x87_subnormal_direction(rays) {
                assert_eq!(
                    visits(&counters),
                    visits(&alone),
                    "packet work counted in mode {name}"
                );
            }
            self.shared_starts += u64::from(counters.blocks != alone.blocks);
            self.blocks_saved += alone.blocks as i64 - counters.blocks as i64;
        }
        reference
    }

    /// `intersect` (f32) in every mode; panics on any disagreement.
    pub fn intersect(
        &mut self,
        field: &HeightField<'_>,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<FieldHit> {
        self.queries += 1;
        let flat = field.clone().with_traversal(Traversal::Flat);
        let (reference, occluded) = at_precision(24, || {
            (
                flat.intersect(ray, t_min, t_max),
                flat.occludes(ray, t_min, t_max, &mut Counters::default()),
            )
        });
        assert_eq!(occluded, reference.is_some());
        for (name, (r, occ)) in self.each(field, |g, _| {
            at_precision(24, || {
                (
                    g.intersect(ray, t_min, t_max),
                    g.occludes(ray, t_min, t_max, &mut Counters::default()),
                )
            })
        }) {
            let same = match (&reference, &r) {
                (None, None) => true,
                (Some(a), Some(b)) => {
                    a.t.to_bits() == b.t.to_bits()
                        && (a.cell_x, a.cell_z, a.triangle) == (b.cell_x, b.cell_z, b.triangle)
                        && a.local.0.to_bits() == b.local.0.to_bits()
                        && a.local.1.to_bits() == b.local.1.to_bits()
                }
                _ => false,
            };
            assert!(
                same && occ == occluded,
                "mode {name} differs from the flat walk: {r:?} vs {reference:?} \
                 (ray {ray:?} t=[{t_min},{t_max}] field {}x{})",
                field.width(),
                field.depth()
            );
        }
        reference
    }
}

/// On an x87 target, whether a lane's direction has a subnormal
/// component (the odd lane `d·1e-39` of `tests/modes.rs`: every component
/// subnormal, the reciprocals past `f32::MAX`, walked by
/// `traversal::nearest`'s branch for tiny directions). 24-bit precision
/// rounds each operation's significand as `f32` does but keeps the x87's
/// wider exponent range in registers, so values outside `f32`'s range
/// (the firmware README's caveat) depend on where the compiler stores
/// them. Measured on such a ray (seed 21): the same hits, but other
/// triangle tests, and not one count: the ray copied into all eight
/// lanes of one packet tested 44 triangles against its own walks' 64
/// (32 on x86-64), so the lanes' walks differ with register allocation,
/// not by a start. With `d·1e-30` instead (reciprocals within range) every
/// count matches. The hits are still checked. Elsewhere, `false`.
fn x87_subnormal_direction(rays: &[Ray; LANES]) -> bool {
    cfg!(all(target_arch = "x86", not(target_feature = "sse2")))
        && rays
            .iter()
            .any(|r| r.direction.to_array().iter().any(|c| c.is_subnormal()))
}

/// Both packet entries on `field`: the hits, the `t`s, the work counted by
/// `intersect_packet`, and the work its rays count one by one.
fn packet_hits(
    field: &HeightField<'_>,
    packet: &RayPacket,
    t_min: f32,
    t_max: f32,
) -> (
    [Option<FieldHit>; LANES],
    [Option<f32>; LANES],
    Counters,
    Counters,
) {
    let mut counters = Counters::default();
    let hits = field.intersect_packet(packet, t_min, t_max, &mut counters);
    let ts = field.intersect_t_packet(packet, t_min, t_max, &mut Counters::default());
    let mut alone = Counters::default();
    for l in 0..LANES {
        field.intersect_counted(&packet.ray(l), t_min, t_max, &mut alone);
    }
    (hits, ts, counters, alone)
}

fn same_field_hit(a: &Option<FieldHit>, b: &Option<FieldHit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.t.to_bits() == b.t.to_bits()
                && (a.cell_x, a.cell_z, a.triangle) == (b.cell_x, b.cell_z, b.triangle)
                && a.local.0.to_bits() == b.local.0.to_bits()
                && a.local.1.to_bits() == b.local.1.to_bits()
                && a.point.to_array().map(f32::to_bits) == b.point.to_array().map(f32::to_bits)
        }
        _ => false,
    }
}
