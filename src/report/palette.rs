//! One colour per interface point and per actuator, the same in every figure: a reader who
//! has learnt that the left leg is orange finds it orange in the forces, the spectra, the
//! powers and the transfer functions. Series are coloured by what they are, never by their
//! place in a legend; everything else keeps the plot's colour cycle.

use super::plot::{palette_color, Series, SeriesStyle, PALETTE};
use crate::actuator::{link_id, Actuator, Frame};
use crate::analysis::series::LinkSeries;
use plotters::style::RGBColor;

/// Palette slots of the points: the frame's stack foot, left and right leg, the inertial
/// actuator's foot. The actuators take the slots after them, in case order.
const STACK: usize = 0;
const LEFT_LEG: usize = 1;
const RIGHT_LEG: usize = 2;
const INERTIAL_FOOT: usize = 3;
const FIRST_ACTUATOR: usize = 4;

/// The colour of the point where link `link` of an actuator of kind `kind` stands.
pub fn point(kind: &str, link: &str) -> RGBColor {
    palette_color(match (kind, link) {
        ("inertial", _) => INERTIAL_FOOT,
        (_, "left_leg") => LEFT_LEG,
        (_, "right_leg") => RIGHT_LEG,
        _ => STACK,
    })
}

/// The colour of actuator `a` (case order), where a series or a bar stands for a whole
/// actuator.
pub fn actuator(a: usize) -> RGBColor {
    palette_color(FIRST_ACTUATOR + a % (PALETTE.len() - FIRST_ACTUATOR))
}

/// Colours of quantities that are neither a point nor an actuator but sit beside them
/// (the parts of a stack's force): slots no point takes, so that none reads as a point.
pub fn part(i: usize) -> RGBColor {
    const PARTS: [usize; 3] = [9, 8, 6];
    palette_color(PARTS[i % PARTS.len()])
}

/// The colour of a link's point.
pub fn link(actuators: &[Actuator], l: &LinkSeries) -> RGBColor {
    point(actuators.get(l.actuator).map_or("", |a| a.kind()), &l.name)
}

/// The actuator and colour of a point named `<actuator>_<link>` (as in results and
/// summaries), if it is one.
fn named(actuators: &[Actuator], name: &str) -> Option<(usize, RGBColor)> {
    actuators.iter().enumerate().find_map(|(a, act)| {
        let links: &[&str] = if act.kind() == "frame" { &Frame::LINKS } else { &["stack"] };
        links.iter().find(|l| link_id(act.name(), l) == name).map(|l| (a, point(act.kind(), l)))
    })
}

/// A series of the point named `name` in its colour; lines of a second or later actuator
/// dashed, so that two frames' left legs in one panel stay apart.
pub fn point_series(actuators: &[Actuator], name: &str, s: Series) -> Series {
    match named(actuators, name) {
        Some((a, c)) if a > 0 && s.style == SeriesStyle::Line => s.coloured(c).with_style(SeriesStyle::Dashed),
        Some((_, c)) => s.coloured(c),
        None => s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_point_and_actuator_has_its_own_colour() {
        let points = [point("frame", "stack"), point("frame", "left_leg"), point("frame", "right_leg")];
        let mut all: Vec<RGBColor> = points.to_vec();
        all.push(point("inertial", "stack"));
        all.extend((0..3).map(actuator));
        for (i, a) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|b| b != a), "colour {i} repeats: {all:?}");
        }
        // The same point, the same colour, whatever else a figure holds.
        assert_eq!(point("frame", "left_leg"), point("frame", "left_leg"));
    }
}
