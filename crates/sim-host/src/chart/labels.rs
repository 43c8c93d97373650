//! Label placement without overlaps: each label tries a ring of positions around
//! its anchor, nearest first, and takes the first one inside the bounds that
//! touches no placed label and no obstacle (the chart's markers, its legend); a
//! label with no free position is dropped, never drawn over something.

/// A pixel rectangle, `x0..x1` × `y0..y1` (ends excluded).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    /// Left edge.
    pub x0: i32,
    /// Top edge.
    pub y0: i32,
    /// Right edge (excluded).
    pub x1: i32,
    /// Bottom edge (excluded).
    pub y1: i32,
}

impl Rect {
    /// A `w` × `h` rectangle with its top-left corner at (`x`, `y`).
    pub fn at(x: i32, y: i32, w: i32, h: i32) -> Rect {
        Rect {
            x0: x,
            y0: y,
            x1: x + w,
            y1: y + h,
        }
    }

    /// A square of half-side `r` around (`x`, `y`).
    pub fn around(x: i32, y: i32, r: i32) -> Rect {
        Rect {
            x0: x - r,
            y0: y - r,
            x1: x + r + 1,
            y1: y + r + 1,
        }
    }

    /// Whether the two rectangles share a pixel.
    pub fn intersects(&self, o: &Rect) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }

    /// Whether `o` lies inside `self`.
    pub fn contains(&self, o: &Rect) -> bool {
        o.x0 >= self.x0 && o.y0 >= self.y0 && o.x1 <= self.x1 && o.y1 <= self.y1
    }
}

/// The box a label of `chars` characters of the pixel font takes at scale 1 with
/// its top-left text pixel at (`x`, `y`), white margin included (what
/// [`super::plot::Canvas::finish`] paints).
pub fn text_box(x: i32, y: i32, chars: usize) -> Rect {
    Rect {
        x0: x - 1,
        y0: y - 1,
        x1: x + 6 * chars as i32,
        y1: y + 10,
    }
}

/// Places labels of `chars[i]` characters near `anchors[i]`, in the given order
/// (earlier labels win): the text's top-left corner, or `None` for a dropped label.
/// No two placed boxes ([`text_box`]) intersect, none intersects an obstacle, all
/// lie inside `bounds`.
pub fn place(
    anchors: &[(i32, i32)],
    chars: &[usize],
    obstacles: &[Rect],
    bounds: Rect,
) -> Vec<Option<(i32, i32)>> {
    let mut placed: Vec<Rect> = Vec::new();
    let mut out = Vec::with_capacity(anchors.len());
    for (&(ax, ay), &n) in anchors.iter().zip(chars) {
        let w = 6 * n as i32;
        let h = 9;
        let mut spot = None;
        'search: for d in [5, 12, 22, 34] {
            let candidates = [
                (ax + d, ay - h / 2),
                (ax - d - w, ay - h / 2),
                (ax - w / 2, ay - d - h),
                (ax - w / 2, ay + d),
                (ax + d, ay - d - h),
                (ax + d, ay + d),
                (ax - d - w, ay - d - h),
                (ax - d - w, ay + d),
            ];
            for (x, y) in candidates {
                let b = text_box(x, y, n);
                if bounds.contains(&b)
                    && !placed.iter().any(|p| p.intersects(&b))
                    && !obstacles.iter().any(|o| o.intersects(&b))
                {
                    spot = Some((x, y));
                    placed.push(b);
                    break 'search;
                }
            }
        }
        out.push(spot);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intersection_is_strict_on_edges() {
        let a = Rect::at(0, 0, 10, 10);
        assert!(a.intersects(&Rect::at(9, 9, 5, 5)));
        assert!(!a.intersects(&Rect::at(10, 0, 5, 5)));
        assert!(!a.intersects(&Rect::at(0, 10, 5, 5)));
    }

    /// Crowded random anchors (a fixed pseudo-random sequence): no two placed
    /// boxes intersect, none covers a marker, all lie inside the bounds, and a
    /// crowd this dense drops some labels rather than overlap.
    #[test]
    fn placed_labels_never_overlap_each_other_or_markers() {
        let bounds = Rect::at(0, 0, 400, 300);
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut next = |m: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % m) as i32
        };
        let anchors: Vec<(i32, i32)> = (0..200).map(|_| (next(400), next(300))).collect();
        let chars: Vec<usize> = (0..200).map(|_| 3 + next(12) as usize).collect();
        let markers: Vec<Rect> = anchors
            .iter()
            .map(|&(x, y)| Rect::around(x, y, 3))
            .collect();
        let spots = place(&anchors, &chars, &markers, bounds);
        let boxes: Vec<Rect> = spots
            .iter()
            .zip(&chars)
            .filter_map(|(s, &n)| s.map(|(x, y)| text_box(x, y, n)))
            .collect();
        assert!(boxes.len() > 10, "only {} placed", boxes.len());
        assert!(
            boxes.len() < anchors.len(),
            "a crowd this dense must drop some"
        );
        for (i, a) in boxes.iter().enumerate() {
            assert!(bounds.contains(a), "{a:?} outside");
            for b in &boxes[i + 1..] {
                assert!(!a.intersects(b), "{a:?} overlaps {b:?}");
            }
            for m in &markers {
                assert!(!a.intersects(m), "{a:?} covers marker {m:?}");
            }
        }
    }

    #[test]
    fn a_lone_label_goes_right_of_its_anchor() {
        let s = place(&[(100, 100)], &[5], &[], Rect::at(0, 0, 400, 300));
        assert_eq!(s, vec![Some((105, 96))]);
    }
}
