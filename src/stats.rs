//! A render's counters ([`Stats`]), apart from the renderer so that the
//! shading it calls can count into them.

use crate::traversal::Counters;

/// Counters of a render, as the thesis counted its work.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Camera rays traced (one per sample).
    pub primary_rays: u64,
    /// Shadow rays (one per light per lit hit facing the light).
    pub shadow_rays: u64,
    /// Reflected rays traced.
    pub reflected_rays: u64,
    /// Rays continued through transparent surfaces.
    pub transmitted_rays: u64,
    /// Primary, reflected and transmitted rays that hit an object.
    pub hits: u64,
    /// Shadow rays that were blocked or filtered.
    pub shadow_hits: u64,
    /// Height-field cells the walks stepped through.
    pub cells: u64,
    /// Triangle pieces the cell tests examined.
    pub triangle_tests: u64,
    /// Skip-grid blocks the walks tested.
    pub blocks: u64,
    /// Primary rays whose walk resumed where the ray below stopped
    /// ([`render_coherent`](crate::render::render_coherent)).
    pub resumed: u64,
    /// Secondary rays not traced because the fixed pending-ray stack was
    /// full or the per-pixel segment cap was reached (0 in sane scenes).
    pub dropped_rays: u64,
    /// Rows handed to the sink.
    pub rows: u32,
    /// The sink stopped the render.
    pub cancelled: bool,
}

impl Stats {
    /// All rays traced, of every kind.
    pub fn rays(&self) -> u64 {
        self.primary_rays + self.shadow_rays + self.reflected_rays + self.transmitted_rays
    }

    /// Adds the height-field work counters.
    pub fn add_work(&mut self, c: &Counters) {
        self.cells += c.cells;
        self.triangle_tests += c.triangle_tests;
        self.blocks += c.blocks;
        self.resumed += c.resumed;
    }

    /// Adds another render's counters (e.g. one per thread or band);
    /// `cancelled` if either was.
    pub fn merge(&mut self, o: &Stats) {
        self.primary_rays += o.primary_rays;
        self.shadow_rays += o.shadow_rays;
        self.reflected_rays += o.reflected_rays;
        self.transmitted_rays += o.transmitted_rays;
        self.hits += o.hits;
        self.shadow_hits += o.shadow_hits;
        self.cells += o.cells;
        self.triangle_tests += o.triangle_tests;
        self.blocks += o.blocks;
        self.resumed += o.resumed;
        self.dropped_rays += o.dropped_rays;
        self.rows += o.rows;
        self.cancelled |= o.cancelled;
    }
}
