//! Legends drawn into the finished picture on the CPU: the strain colour
//! bar with its range and the largest strain, and the colours of the
//! constraint kinds, in a small built-in 3 x 5 pixel font.

use image::{Rgba, RgbaImage};

/// Rows of a glyph, top first; the three low bits of each are its pixels,
/// left to right.
fn glyph(c: char) -> [u8; 5] {
    match c.to_ascii_uppercase() {
        '0' => [0b111, 0b101, 0b101, 0b101, 0b111],
        '1' => [0b010, 0b110, 0b010, 0b010, 0b111],
        '2' => [0b111, 0b001, 0b111, 0b100, 0b111],
        '3' => [0b111, 0b001, 0b111, 0b001, 0b111],
        '4' => [0b101, 0b101, 0b111, 0b001, 0b001],
        '5' => [0b111, 0b100, 0b111, 0b001, 0b111],
        '6' => [0b111, 0b100, 0b111, 0b101, 0b111],
        '7' => [0b111, 0b001, 0b001, 0b001, 0b001],
        '8' => [0b111, 0b101, 0b111, 0b101, 0b111],
        '9' => [0b111, 0b101, 0b111, 0b001, 0b111],
        '.' => [0, 0, 0, 0, 0b010],
        '%' => [0b101, 0b001, 0b010, 0b100, 0b101],
        '+' => [0, 0b010, 0b111, 0b010, 0],
        '-' => [0, 0, 0b111, 0, 0],
        ':' => [0, 0b010, 0, 0b010, 0],
        'A' => [0b010, 0b101, 0b111, 0b101, 0b101],
        'B' => [0b110, 0b101, 0b110, 0b101, 0b110],
        'C' => [0b011, 0b100, 0b100, 0b100, 0b011],
        'D' => [0b110, 0b101, 0b101, 0b101, 0b110],
        'E' => [0b111, 0b100, 0b110, 0b100, 0b111],
        'F' => [0b111, 0b100, 0b110, 0b100, 0b100],
        'H' => [0b101, 0b101, 0b111, 0b101, 0b101],
        'I' => [0b111, 0b010, 0b010, 0b010, 0b111],
        'L' => [0b100, 0b100, 0b100, 0b100, 0b111],
        'M' => [0b101, 0b111, 0b111, 0b101, 0b101],
        'N' => [0b110, 0b101, 0b101, 0b101, 0b101],
        'O' => [0b010, 0b101, 0b101, 0b101, 0b010],
        'R' => [0b110, 0b101, 0b110, 0b101, 0b101],
        'S' => [0b011, 0b100, 0b010, 0b001, 0b110],
        'T' => [0b111, 0b010, 0b010, 0b010, 0b010],
        'U' => [0b101, 0b101, 0b101, 0b101, 0b111],
        'V' => [0b101, 0b101, 0b101, 0b101, 0b010],
        'X' => [0b101, 0b101, 0b010, 0b101, 0b101],
        'Y' => [0b101, 0b101, 0b010, 0b010, 0b010],
        _ => [0; 5],
    }
}

/// Pixels per font pixel for a picture `height` pixels high.
fn font_scale(height: u32) -> u32 {
    (height / 160).clamp(1, 4)
}

fn fill(img: &mut RgbaImage, x: u32, y: u32, w: u32, h: u32, color: [u8; 3], alpha: f32) {
    for py in y..(y + h).min(img.height()) {
        for px in x..(x + w).min(img.width()) {
            let Rgba([r, g, b, _]) = *img.get_pixel(px, py);
            let mix = |old: u8, new: u8| (old as f32 * (1.0 - alpha) + new as f32 * alpha) as u8;
            img.put_pixel(
                px,
                py,
                Rgba([mix(r, color[0]), mix(g, color[1]), mix(b, color[2]), 255]),
            );
        }
    }
}

/// Writes `text` with its top-left corner at `(x, y)`; returns its width.
fn text(img: &mut RgbaImage, x: u32, y: u32, text: &str, scale: u32) -> u32 {
    for (i, c) in text.chars().enumerate() {
        let left = x + i as u32 * 4 * scale;
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..3 {
                if bits & (0b100 >> col) != 0 {
                    let (px, py) = (left + col * scale, y + row as u32 * scale);
                    fill(img, px, py, scale, scale, [20, 20, 24], 1.0);
                }
            }
        }
    }
    text_width(text, scale)
}

fn text_width(text: &str, scale: u32) -> u32 {
    (text.chars().count() as u32 * 4).saturating_sub(1) * scale
}

/// The strain colour map of cloth.wgsl at `t` in `[0, 1]`, as sRGB bytes.
pub fn strain_color(t: f32) -> [u8; 3] {
    let x = t.clamp(0.0, 1.0) * 4.0;
    let linear = [
        (x - 2.0).clamp(0.0, 1.0),
        x.clamp(0.0, 1.0) - (x - 3.0).clamp(0.0, 1.0),
        1.0 - (x - 1.0).clamp(0.0, 1.0),
    ];
    linear.map(|c| (linear_to_srgb(c) * 255.0).round() as u8)
}

/// The sRGB encoding of a linear value in `[0, 1]`.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// A percentage with one decimal for small values.
fn percent(x: f32) -> String {
    if x < 0.1 {
        format!("{:.1}%", x * 100.0)
    } else {
        format!("{:.0}%", x * 100.0)
    }
}

/// The strain legend at the right edge: a colour bar from 0 (bottom) to
/// `range` (top), and the largest strain in the picture.
pub fn draw_strain_legend(img: &mut RgbaImage, range: f32, max_strain: f32) {
    let s = font_scale(img.height());
    let (bar_w, bar_h) = (6 * s, img.height() / 2);
    let top_label = format!("{}+", percent(range));
    let max_label = format!("MAX {}", percent(max_strain));
    let panel_w = bar_w + 8 * s + text_width(&top_label, s).max(text_width(&max_label, s) / 2);
    let panel_w = panel_w.max(text_width(&max_label, s) + 4 * s);
    let x0 = img.width().saturating_sub(panel_w + 4 * s);
    let y0 = 4 * s;
    let panel_h = bar_h + 26 * s;
    fill(img, x0, y0, panel_w, panel_h, [255, 255, 255], 0.8);
    text(img, x0 + 2 * s, y0 + 2 * s, "STRAIN", s);
    let (bx, by) = (x0 + 2 * s, y0 + 10 * s);
    for row in 0..bar_h {
        let t = 1.0 - row as f32 / (bar_h - 1).max(1) as f32;
        fill(img, bx, by + row, bar_w, 1, strain_color(t), 1.0);
    }
    let lx = bx + bar_w + 2 * s;
    text(img, lx, by, &top_label, s);
    text(img, lx, by + bar_h / 2 - 2 * s, &percent(range / 2.0), s);
    text(img, lx, by + bar_h - 5 * s, "0%", s);
    text(img, x0 + 2 * s, by + bar_h + 4 * s, &max_label, s);
}

/// Swatches and names of the constraint kinds (name and linear colour) at
/// the top-left corner.
pub fn draw_constraint_legend(img: &mut RgbaImage, kinds: &[(&str, [f32; 3])]) {
    let s = font_scale(img.height());
    let widest = kinds
        .iter()
        .map(|(n, _)| text_width(n, s))
        .max()
        .unwrap_or(0);
    let (x0, y0) = (4 * s, 4 * s);
    let row = 8 * s;
    fill(
        img,
        x0,
        y0,
        widest + 14 * s,
        row * kinds.len() as u32 + 2 * s,
        [255, 255, 255],
        0.8,
    );
    for (i, (name, color)) in kinds.iter().enumerate() {
        let y = y0 + 2 * s + i as u32 * row;
        let srgb = color.map(|c| (linear_to_srgb(c) * 255.0).round() as u8);
        fill(img, x0 + 2 * s, y, 8 * s, 5 * s, srgb, 1.0);
        text(img, x0 + 12 * s, y, name, s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_map_runs_from_blue_to_red() {
        let [r, _, b] = strain_color(0.0);
        assert!(b > 200 && r < 30);
        let [r, _, b] = strain_color(1.0);
        assert!(r > 200 && b < 30);
    }

    #[test]
    fn legends_draw_inside_the_picture() {
        let mut img = RgbaImage::from_pixel(200, 120, Rgba([0, 0, 0, 255]));
        draw_strain_legend(&mut img, 0.1, 0.042);
        draw_constraint_legend(&mut img, &[("stretch", [0.1, 0.5, 0.9])]);
        // Something was drawn, and a tiny picture does not panic.
        assert!(img.pixels().any(|p| p.0[0] > 100));
        draw_strain_legend(&mut RgbaImage::new(3, 2), 0.1, 1.0);
    }
}
