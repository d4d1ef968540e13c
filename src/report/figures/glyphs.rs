//! Text on bitmap figures, each glyph at its pen position plus its left side bearing.
//!
//! plotters' own glyph drawing (its `ab_glyph` font) places each glyph's bitmap at the pen
//! position without the glyph's bearing, so narrow glyphs and those that reach left of the pen
//! (`_`, `i`, `l`) land beside their neighbours ("D ± D _err", "radi i"). [`Glyphs`] wraps a
//! backend and draws text itself with the same embedded font, the same size, anchors, rotation
//! and vertical placement as plotters, only with the bearing; everything else goes to the wrapped
//! backend unchanged. SVG figures carry their text as text and need none of this.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, ScaleFont};
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// The embedded font (the one plotters draws with as "sans-serif", [`super::register_font`]).
fn font() -> &'static FontRef<'static> {
    static FONT: OnceLock<FontRef<'static>> = OnceLock::new();
    FONT.get_or_init(|| {
        FontRef::try_from_slice(super::FONT_BYTES).expect("the embedded DejaVu Sans parses")
    })
}

/// A drawing backend whose text is drawn glyph by glyph, each at its pen position plus its left
/// side bearing (plotters' own drawing leaves the bearing out: "D ± D _err"); everything else
/// goes to the wrapped backend unchanged.
pub struct Glyphs<B>(pub B);

/// The pixels of `text` at `size` pixels, as (x, y, coverage) from the layout box's top left
/// (the baseline at half the size, as plotters places it), and the box's width and height.
fn rasterize(text: &str, size: f64) -> (Vec<(i32, i32, f32)>, i32, i32) {
    let scaled = font().as_scaled(size as f32);
    let mut pixels = Vec::new();
    let mut pen = 0f32;
    let mut previous = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            pen += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(scaled.scale(), ab_glyph::point(pen, 0.0));
        if let Some(outline) = scaled.outline_glyph(glyph) {
            let bounds = outline.px_bounds();
            let (x0, y0) = (
                bounds.min.x as i32,
                (size as f32 / 2.0 + bounds.min.y) as i32,
            );
            outline.draw(|x, y, a| pixels.push((x0 + x as i32, y0 + y as i32, a)));
        }
        pen += scaled.h_advance(id);
        previous = Some(id);
    }
    (pixels, pen as i32, (size / 1.24) as i32)
}

impl<B: DrawingBackend> DrawingBackend for Glyphs<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        (iw, ih): (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, (iw, ih), src)
    }

    /// As plotters' default (anchor, rotation, clipping), with the glyphs of `rasterize`.
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let (pixels, width, height) = rasterize(text, style.size());
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let turn = style.transform();
        let (w, h) = self.get_size();
        for (x, y, a) in pixels {
            let (x, y) = turn.transform(x + dx, y + dy);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                self.0.draw_pixel((x, y), color.mix(f64::from(a)))?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The columns of ink of `text`, left to right, as runs of inked columns.
    fn ink_runs(text: &str) -> Vec<(i32, i32)> {
        let (pixels, _, _) = rasterize(text, 40.0);
        let mut cols: Vec<i32> = pixels.iter().filter(|p| p.2 > 0.3).map(|p| p.0).collect();
        cols.sort_unstable();
        cols.dedup();
        let mut runs: Vec<(i32, i32)> = Vec::new();
        for c in cols {
            match runs.last_mut() {
                Some(r) if c == r.1 + 1 => r.1 = c,
                _ => runs.push((c, c)),
            }
        }
        runs
    }

    /// Each glyph's ink starts at its pen position plus its left side bearing, as the font's
    /// metrics say: the D of "D_" 4 px right of the pen at 40 px, and the underscore after it
    /// at the D's advance plus its own bearing, so the gap between their inks is the font's,
    /// not a stray space. (Broken on purpose — `bounds.min.x` left out of `x0`, as plotters
    /// draws — the D starts at 0 and the gap grows by the D's bearing: the test fails.)
    #[test]
    fn glyphs_sit_at_their_bearings() {
        let scaled = font().as_scaled(40.0);
        let (d, u) = (scaled.glyph_id('D'), scaled.glyph_id('_'));
        let runs = ink_runs("D_");
        let alone = ink_runs("D");
        let d_ink = (alone[0].0, alone.last().unwrap().1);
        let bearing = scaled.h_side_bearing(d);
        assert!(
            (d_ink.0 as f32 - bearing).abs() <= 1.0,
            "{d_ink:?} {bearing}"
        );
        let expected_gap = scaled.h_advance(d) + scaled.kern(d, u) + scaled.h_side_bearing(u)
            - (d_ink.1 + 1) as f32;
        let underscore = runs
            .iter()
            .find(|r| r.0 > d_ink.1)
            .map_or(d_ink.1 + 1, |r| r.0);
        let gap = (underscore - (d_ink.1 + 1)) as f32;
        assert!(
            (gap - expected_gap.max(0.0)).abs() <= 1.5,
            "gap {gap} px between D and _, the font's {expected_gap} ({runs:?})"
        );
    }
}
