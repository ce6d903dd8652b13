//! `softnc path --format svg`: the picture a programmer checks before cutting. Programmed
//! contour, tool-centre path coloured by role, the tool circle at each block end, block labels
//! and alarms, on a grid in the compensation plane (docs/path-format.md).

use nc_kernel::geometry::{tip_offset, Curve, Fineness};
use nc_kernel::Alarm;
use nc_kernel::{Block, MotionKind, Plane, Pos, TrcSide, AXIS_NAMES};
use nc_kernel::{Interpreter, MachineData, ToolTable};
use nc_kernel::{MachineKind, ToolPost};
use nc_kernel::{Role, Segment, Shape};
use std::f64::consts::TAU;
use svg::node::element::path::Data;
use svg::node::element::{
    Circle, ClipPath, Definitions, Group, Line, Path, Rectangle, Text, Title,
};
use svg::Document;

/// Above this many motion blocks the picture leaves out labels and tool circles: they would
/// cover the path.
const MAX_ANNOTATED_BLOCKS: usize = 400;
/// Plot area, px.
const PLOT_W: f64 = 900.0;
const PLOT_H_MAX: f64 = 640.0;
const LEFT: f64 = 64.0;
const TOP: f64 = 64.0;
const RIGHT: f64 = 96.0;

const INK: &str = "#1f2328";
const GRID: &str = "#e6e8eb";
const PROGRAMMED: &str = "#1f2328";
const CONTOUR: &str = "#0b63c5";
const APPROACH: &str = "#1a7f37";
const CORNER: &str = "#d4650a";
const UNCOMP: &str = "#6e7781";
const ALARM: &str = "#cf222e";
const ACTUAL: &str = "#8250df";

/// Points on an arc for the bounding box and for arcs that change radius: every 2.5°.
const FINE: Fineness = Fineness {
    max_angle: TAU / 144.0,
    max_length: f64::INFINITY,
};

/// What the picture shows, gathered before drawing.
pub struct Picture<'a> {
    name: &'a str,
    md: &'a MachineData,
    blocks: Vec<Block>,
    segments: &'a [Segment],
    alarm: Option<&'a Alarm>,
    plane: Plane,
    /// The axes' actual positions (softnc run), drawn over the path.
    actual: &'a [Pos],
}

impl<'a> Picture<'a> {
    /// `segments` and `alarm` are what preparation gave; the programmed contour is read again
    /// from the source by the interpreter (up to its first alarm, if any).
    pub fn new(
        name: &'a str,
        source: &'a str,
        md: &'a MachineData,
        tools: &'a ToolTable,
        segments: &'a [Segment],
        alarm: Option<&'a Alarm>,
    ) -> Self {
        let blocks: Vec<Block> = Interpreter::new(name, source, md, tools)
            .map_while(Result::ok)
            .collect();
        // The compensation plane if the program compensates, else the first plane moved in.
        let plane = blocks
            .iter()
            .filter_map(|b| b.motion.map(|m| (b.modal.trc, m.plane)))
            .find(|(t, _)| *t != TrcSide::Off)
            .or_else(|| {
                blocks
                    .iter()
                    .find_map(|b| b.motion.map(|m| (TrcSide::Off, m.plane)))
            })
            .map_or(Plane::XY, |(_, p)| p);
        Picture {
            name,
            md,
            blocks,
            segments,
            alarm,
            plane,
            actual: &[],
        }
    }

    /// Adds the actual path the axes took.
    pub fn with_actual(mut self, actual: &'a [Pos]) -> Self {
        self.actual = actual;
        self
    }

    fn uv(&self, p: Pos) -> (f64, f64) {
        (
            p[self.plane.abscissa as usize],
            p[self.plane.ordinate as usize],
        )
    }

    /// The blocks whose end gets a label and, when compensated, a tool circle.
    fn annotated(&self) -> bool {
        self.blocks.iter().filter(|b| b.motion.is_some()).count() <= MAX_ANNOTATED_BLOCKS
    }

    /// Tool circles: (centre, radius, tooltip) at the end of each block's last compensated
    /// segment.
    fn tool_circles(&self) -> Vec<((f64, f64), f64, String)> {
        let mut out = Vec::new();
        let mut last_r = 0.0;
        let centre = if self.turning_tips() {
            "nose centre"
        } else {
            "tool centre"
        };
        for (i, s) in self.segments.iter().enumerate() {
            let block_ends = self
                .segments
                .get(i + 1)
                .is_none_or(|n| n.source.line != s.source.line || n.source.col != s.source.col);
            if !block_ends || s.role == Role::Uncompensated {
                continue;
            }
            let block = self
                .blocks
                .iter()
                .find(|b| b.line == s.source.line && b.col == s.source.col);
            let r = block.map_or(0.0, |b| b.modal.radius.abs());
            // A D0 deselection block ends with no radius: the tool still has the last one.
            let r = if r > 0.0 { r } else { last_r };
            last_r = r;
            if r > 0.0 {
                let names = ["X", "Y", "Z"];
                // A turning tool's path is its tip P: the nose centre is P minus the cutting
                // edge position's vector.
                let v = block.map_or([0.0, 0.0], |b| {
                    tip_offset(b.modal.edge, b.modal.radius, self.plane)
                });
                let p = self.uv(s.to);
                let c = (p.0 - v[0], p.1 - v[1]);
                let tip = format!(
                    "{}: {} {}{} {}{}, R{}",
                    s.source
                        .number
                        .map_or_else(|| format!("line {}", s.source.line), |n| n.to_string()),
                    centre,
                    names[self.plane.abscissa as usize],
                    num(c.0),
                    names[self.plane.ordinate as usize],
                    num(c.1),
                    num(r)
                );
                out.push((c, r, tip));
            }
        }
        out
    }

    /// A segment's arc in the picture's plane, if it is one.
    fn arc(&self, s: &Segment) -> Option<Curve> {
        match s.shape {
            Shape::Arc { plane, .. } if plane == self.plane => Curve::new(s),
            _ => None,
        }
    }

    /// Points along a segment in the plane, for the bounding box and radius-changing arcs.
    fn sample(&self, s: &Segment) -> Vec<(f64, f64)> {
        self.polyline(self.arc(s).as_ref(), s.from, s.to)
    }

    /// The ends of a piece and, for an arc, the points between them.
    fn polyline(&self, arc: Option<&Curve>, from: Pos, to: Pos) -> Vec<(f64, f64)> {
        let inner = arc.into_iter().flat_map(|c| c.interior(FINE));
        std::iter::once(from)
            .chain(inner)
            .chain(std::iter::once(to))
            .map(|p| self.uv(p))
            .collect()
    }

    fn programmed_elements(&self) -> Vec<ProgElem> {
        self.blocks
            .iter()
            .filter_map(|b| {
                let m = b.motion?;
                let arc = (m.kind.is_arc() && m.plane == self.plane)
                    .then(|| Curve::of_motion(&m))
                    .flatten();
                Some(ProgElem {
                    from: self.uv(m.start),
                    to: self.uv(m.end),
                    points: self.polyline(arc.as_ref(), m.start, m.end),
                    arc,
                    rapid: m.kind == MotionKind::Rapid,
                    line: b.line,
                })
            })
            .collect()
    }

    pub fn render(&self) -> Document {
        let prog = self.programmed_elements();
        let circles = if self.annotated() {
            self.tool_circles()
        } else {
            Vec::new()
        };

        let (bb, framed) = self.frame(&prog, &circles);
        let (w, h) = bb.size();
        // Room for the labels at the edges: 4 % of the size, at least ~48 px.
        let scale0 = (PLOT_W / w.max(1e-9)).min(PLOT_H_MAX / h.max(1e-9));
        let pad = (0.04 * w.max(h).max(1.0)).max(48.0 / scale0);
        let (min_u, min_v) = (bb.min.0 - pad, bb.min.1 - pad);
        let (w, h) = (w + 2.0 * pad, h + 2.0 * pad);
        let scale = (PLOT_W / w).min(PLOT_H_MAX / h);
        let plot_h = h * scale;
        // A lathe tool in front of the centre of rotation: X drawn downwards (840C ch. 11).
        let mirrored = self.md.machine == MachineKind::Turning
            && self.md.tool_post == ToolPost::InFront
            && self.plane == Plane::ZX;
        let view = View {
            min_u,
            min_v,
            scale,
            plot_h,
            mirrored,
        };

        let legend_y = TOP + plot_h + 40.0;
        let alarm_lines = usize::from(self.alarm.is_some());
        let extra = alarm_lines + usize::from(self.actual.len() > 1);
        let height = legend_y + 44.0 + 20.0 * extra as f64;
        let width = LEFT + w * scale + RIGHT;
        let width = width.max(LEFT + PLOT_W + RIGHT);

        let mut doc = Document::new()
            .set("xmlns", "http://www.w3.org/2000/svg")
            .set("viewBox", (0, 0, width.ceil() as i64, height.ceil() as i64))
            .set("width", width.ceil() as i64)
            .set("height", height.ceil() as i64)
            .set("font-family", "DejaVu Sans, Helvetica, Arial, sans-serif")
            .add(
                Rectangle::new()
                    .set("width", "100%")
                    .set("height", "100%")
                    .set("fill", "#ffffff"),
            )
            .add(Title::new(format!("{}: tool-centre path", self.name)));

        doc = doc.add(self.title(&view, framed));
        doc = doc.add(grid(&view, self.plane, w, h));
        // Travel beyond the frame is cut off at its edge.
        doc = doc.add(
            Definitions::new().add(
                ClipPath::new().set("id", "plot").add(
                    Rectangle::new()
                        .set("x", LEFT)
                        .set("y", TOP)
                        .set("width", rd(w * scale))
                        .set("height", rd(plot_h)),
                ),
            ),
        );
        let clipped = |g: Group| g.set("clip-path", "url(#plot)");
        doc = doc.add(clipped(programmed_group(
            &view,
            &prog,
            self.alarm.map(|a| a.line),
        )));
        doc = doc.add(clipped(self.path_group(&view)));
        if self.actual.len() > 1 {
            doc = doc.add(clipped(self.actual_group(&view)));
        }
        if !circles.is_empty() {
            let mut g = Group::new()
                .set("id", "tool-circles")
                .set("fill", "none")
                .set("stroke", CONTOUR)
                .set("stroke-opacity", 0.45)
                .set("stroke-width", 0.8);
            for (c, r, tip) in &circles {
                let (x, y) = view.px(*c);
                g = g.add(
                    Circle::new()
                        .set("cx", rd(x))
                        .set("cy", rd(y))
                        .set("r", rd(r * view.scale))
                        .add(Title::new(tip.as_str())),
                );
            }
            doc = doc.add(clipped(g));
        }
        if self.annotated() {
            doc = doc.add(clipped(self.labels(&view)));
        }
        if let Some(a) = self.alarm {
            doc = doc.add(self.alarm_marker(&view, a));
        }
        doc.add(self.legend(legend_y))
    }

    /// The region the picture shows, and whether it is framed on the cutting moves: where
    /// rapid traverses (to a reference point or a tool change position) would shrink the
    /// work to a corner of the picture, the frame holds the feed moves and the rapids run
    /// out of it; otherwise it holds everything drawn.
    fn frame(&self, prog: &[ProgElem], circles: &[((f64, f64), f64, String)]) -> (Bbox, bool) {
        let (mut all, mut work) = (Bbox::default(), Bbox::default());
        for e in prog {
            for p in &e.points {
                all.add(*p);
                if !e.rapid {
                    work.add(*p);
                }
            }
        }
        for s in self.segments {
            for p in self.sample(s) {
                all.add(p);
                if !s.rapid {
                    work.add(p);
                }
            }
        }
        for p in self.actual {
            all.add(self.uv(*p));
        }
        for (c, r, _) in circles {
            all.add((c.0 - r, c.1 - r));
            all.add((c.0 + r, c.1 + r));
        }
        if all.empty() {
            all.add((0.0, 0.0));
        }
        let ((w, h), (ww, wh)) = (all.size(), work.size());
        // The work keeps at least half the picture in each direction (with some room).
        let small = |a: f64, b: f64| a > 2.0 * b + 0.1 * a.max(1.0);
        if work.n > 1 && (small(w, ww) || small(h, wh)) {
            if let Some(p) = self.alarm.and_then(|a| self.alarm_at(a)) {
                work.add(p);
            }
            for (c, r, _) in circles {
                if work.holds(*c) {
                    work.add((c.0 - r, c.1 - r));
                    work.add((c.0 + r, c.1 + r));
                }
            }
            (work, true)
        } else {
            (all, false)
        }
    }

    fn title(&self, _v: &View, framed: bool) -> Group {
        let mut radii: Vec<(u32, f64)> = Vec::new();
        for b in &self.blocks {
            if b.modal.trc != TrcSide::Off
                && b.modal.d != 0
                && !radii
                    .iter()
                    .any(|(d, r)| *d == b.modal.d && *r == b.modal.radius)
            {
                radii.push((b.modal.d, b.modal.radius));
            }
        }
        let tools = if radii.is_empty() {
            "no tool radius compensation".to_string()
        } else {
            let list: Vec<String> = radii
                .iter()
                .take(6)
                .map(|(d, r)| format!("D{d} R{}", num(*r)))
                .collect();
            format!(
                "tool radius {}{}",
                list.join(", "),
                if radii.len() > 6 { ", …" } else { "" }
            )
        };
        let sub = format!(
            "{} · plane {} · {} blocks · {} segments · {}{}",
            self.md.dialect.as_str(),
            self.plane.name(),
            self.blocks.len(),
            self.segments.len(),
            tools,
            if framed {
                " · framed on the cutting moves, rapid traverses run out of the frame"
            } else {
                ""
            }
        );
        Group::new()
            .set("id", "title")
            .set("fill", INK)
            .add(
                Text::new(self.name)
                    .set("x", LEFT)
                    .set("y", 24)
                    .set("font-size", 17)
                    .set("font-weight", "bold"),
            )
            .add(
                Text::new(sub)
                    .set("x", LEFT)
                    .set("y", 42)
                    .set("font-size", 12)
                    .set("fill", UNCOMP),
            )
    }

    fn path_group(&self, v: &View) -> Group {
        let mut g = Group::new()
            .set("id", "tool-path")
            .set("fill", "none")
            .set("stroke-linecap", "round")
            .set("stroke-linejoin", "round");
        for s in self.segments {
            let (from, to) = (v.px(self.uv(s.from)), v.px(self.uv(s.to)));
            let mut d = Data::new().move_to((from.0 as f32, from.1 as f32));
            let mut zero = (from.0 - to.0).hypot(from.1 - to.1) < 1e-3;
            match (s.shape, self.arc(s)) {
                (
                    Shape::Arc {
                        center,
                        center_end,
                        r0,
                        r1,
                        ..
                    },
                    Some(arc),
                ) => {
                    zero = false;
                    if (r0 - r1).abs() > 1e-12 || center != center_end {
                        for p in self.sample(s).into_iter().skip(1) {
                            let (x, y) = v.px(p);
                            d = d.line_to((x as f32, y as f32));
                        }
                    } else {
                        d = arc_data(d, v, &arc, self.uv(s.to));
                    }
                }
                _ => d = d.line_to((to.0 as f32, to.1 as f32)),
            }
            if zero {
                // A move along the tool axis only: nothing to see in the plane.
                continue;
            }
            let (colour, width, dash) = role_style(s);
            let mut p = Path::new()
                .set("d", d)
                .set("stroke", colour)
                .set("stroke-width", width)
                .set("class", s.role.name());
            if let Some(dash) = dash {
                p = p.set("stroke-dasharray", dash);
            }
            g = g.add(p);
        }
        g
    }

    /// The actual path as one polyline, thinned to points at least half a pixel apart.
    fn actual_group(&self, v: &View) -> Group {
        let mut d = Data::new();
        let mut last: Option<(f64, f64)> = None;
        for p in self.actual {
            let q = v.px(self.uv(*p));
            match last {
                None => d = d.move_to((q.0 as f32, q.1 as f32)),
                Some(l) if (l.0 - q.0).hypot(l.1 - q.1) < 0.5 => continue,
                Some(_) => d = d.line_to((q.0 as f32, q.1 as f32)),
            }
            last = Some(q);
        }
        Group::new().set("id", "actual-path").add(
            Path::new()
                .set("d", d)
                .set("fill", "none")
                .set("stroke", ACTUAL)
                .set("stroke-width", 1.0)
                .set("stroke-linejoin", "round"),
        )
    }

    fn labels(&self, v: &View) -> Group {
        // One label per distinct programmed end point, naming every block that ends there,
        // placed in the widest angular gap between the programmed elements meeting there.
        struct Spot {
            at: (f64, f64),
            names: Vec<String>,
            dirs: Vec<f64>,
        }
        let mut spots: Vec<Spot> = Vec::new();
        let same = |p: (f64, f64), q: (f64, f64)| (p.0 - q.0).hypot(p.1 - q.1) < 1e-6;
        for b in &self.blocks {
            let (Some(m), Some(n)) = (b.motion, b.number) else {
                continue;
            };
            let end = self.uv(m.end);
            match spots.iter_mut().find(|s| same(s.at, end)) {
                // A loop passes the same block many times: name it once.
                Some(s) => {
                    let n = n.to_string();
                    if !s.names.contains(&n) {
                        s.names.push(n);
                    }
                }
                None => spots.push(Spot {
                    at: end,
                    names: vec![n.to_string()],
                    dirs: Vec::new(),
                }),
            }
        }
        for e in self.programmed_elements() {
            let pts = e.points;
            let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
                continue;
            };
            // Directions leaving the start and the end point along the element.
            let leave = |p: (f64, f64), q: Option<&(f64, f64)>| {
                q.filter(|q| !same(p, **q))
                    .map(|q| (q.1 - p.1).atan2(q.0 - p.0))
            };
            let out_of_start = leave(first, pts.get(1));
            let out_of_end = leave(last, pts.len().checked_sub(2).and_then(|i| pts.get(i)));
            for (p, d) in [(first, out_of_start), (last, out_of_end)] {
                if let (Some(s), Some(d)) = (spots.iter_mut().find(|s| same(s.at, p)), d) {
                    s.dirs.push(d);
                }
            }
        }
        let mut g = Group::new()
            .set("id", "labels")
            .set("font-size", 11)
            .set("fill", INK);
        for s in spots {
            let (x, y) = v.px(s.at);
            g = g.add(
                Circle::new()
                    .set("cx", rd(x))
                    .set("cy", rd(y))
                    .set("r", 2.2)
                    .set("fill", PROGRAMMED),
            );
            let a = widest_gap(s.dirs);
            // Screen y points down.
            let (dx, dy) = (a.cos(), -a.sin());
            let (tx, ty) = (x + 9.0 * dx, y + 9.0 * dy + 4.0 + 4.0 * dy);
            let anchor = if dx > 0.35 {
                "start"
            } else if dx < -0.35 {
                "end"
            } else {
                "middle"
            };
            g = g.add(
                Text::new(s.names.join(", "))
                    .set("x", rd(tx))
                    .set("y", rd(ty))
                    .set("text-anchor", anchor),
            );
        }
        g
    }

    fn alarm_marker(&self, v: &View, a: &Alarm) -> Group {
        let (x, y) = v.px(self.alarm_at(a).unwrap_or((v.min_u, v.min_v)));
        Group::new()
            .set("id", "alarm")
            .add(
                Circle::new()
                    .set("cx", rd(x))
                    .set("cy", rd(y))
                    .set("r", 9)
                    .set("fill", "none")
                    .set("stroke", ALARM)
                    .set("stroke-width", 2.5),
            )
            .add(
                Text::new(format!("alarm {}", a.number()))
                    .set("x", rd(x + 13.0))
                    .set("y", rd(y - 10.0))
                    .set("font-size", 12)
                    .set("font-weight", "bold")
                    .set("fill", ALARM),
            )
    }

    /// Where an alarm is marked: at the programmed end of its block, else where the tool path
    /// stopped.
    fn alarm_at(&self, a: &Alarm) -> Option<(f64, f64)> {
        self.blocks
            .iter()
            .find(|b| b.line == a.line)
            .and_then(|b| b.motion.map(|m| self.uv(m.end)))
            .or_else(|| self.segments.last().map(|s| self.uv(s.to)))
    }

    /// A turning tool with a cutting edge position: the path drawn is its tip P.
    fn turning_tips(&self) -> bool {
        self.blocks
            .iter()
            .any(|b| tip_offset(b.modal.edge, b.modal.radius, self.plane) != [0.0, 0.0])
    }

    fn legend(&self, y: f64) -> Group {
        let items: [(&str, &str, f64, Option<&str>); 6] = [
            ("programmed contour", PROGRAMMED, 1.4, None),
            (
                if self.turning_tips() {
                    "tool tip P: contour"
                } else {
                    "tool centre: contour"
                },
                CONTOUR,
                2.2,
                None,
            ),
            ("approach / retract", APPROACH, 2.2, None),
            ("corner / inserted block", CORNER, 2.2, None),
            ("without compensation", UNCOMP, 1.4, None),
            ("rapid", UNCOMP, 1.2, Some("5 4")),
        ];
        let mut g = Group::new().set("id", "legend").set("font-size", 11);
        if self.actual.len() > 1 {
            let (x, y) = (LEFT + 690.0, y + 40.0);
            g = g
                .add(
                    Line::new()
                        .set("x1", x)
                        .set("y1", y - 4.0)
                        .set("x2", x + 22.0)
                        .set("y2", y - 4.0)
                        .set("stroke", ACTUAL)
                        .set("stroke-width", 1.0),
                )
                .add(
                    Text::new("actual path (plc-sim)")
                        .set("x", x + 28.0)
                        .set("y", y)
                        .set("fill", INK),
                );
        }
        // Two rows of three, in columns wide enough for the longest label.
        for (i, (label, colour, width, dash)) in items.into_iter().enumerate() {
            let x = LEFT + 230.0 * (i % 3) as f64;
            let y = y + 20.0 * (i / 3) as f64;
            let mut l = Line::new()
                .set("x1", x)
                .set("y1", y - 4.0)
                .set("x2", x + 22.0)
                .set("y2", y - 4.0)
                .set("stroke", colour)
                .set("stroke-width", width);
            if let Some(d) = dash {
                l = l.set("stroke-dasharray", d);
            }
            g = g.add(l).add(
                Text::new(label)
                    .set("x", x + 28.0)
                    .set("y", y)
                    .set("fill", INK),
            );
        }
        let x = LEFT + 690.0;
        g = g.add(
            Circle::new()
                .set("cx", x + 11.0)
                .set("cy", y - 4.0)
                .set("r", 7)
                .set("fill", "none")
                .set("stroke", CONTOUR)
                .set("stroke-opacity", 0.45),
        );
        g = g.add(
            Text::new("tool at block end")
                .set("x", x + 28.0)
                .set("y", y)
                .set("fill", INK),
        );
        g = g.add(
            Circle::new()
                .set("cx", x + 11.0)
                .set("cy", y + 16.0)
                .set("r", 2.2)
                .set("fill", PROGRAMMED),
        );
        g = g.add(
            Text::new("programmed block end")
                .set("x", x + 28.0)
                .set("y", y + 20.0)
                .set("fill", INK),
        );
        if let Some(a) = self.alarm {
            let block = a.block.as_deref().unwrap_or("");
            g = g.add(
                Text::new(format!(
                    "alarm {} at line {}:{} {}: {}",
                    a.number(),
                    a.line,
                    a.col,
                    block,
                    a.message
                ))
                .set("x", LEFT)
                .set("y", y + 44.0)
                .set("font-size", 12)
                .set("fill", ALARM),
            );
        }
        g
    }
}

/// The bisector of the widest gap between directions (radians); up-right with none.
fn widest_gap(mut dirs: Vec<f64>) -> f64 {
    if dirs.is_empty() {
        return std::f64::consts::FRAC_PI_4;
    }
    dirs.sort_by(f64::total_cmp);
    let mut best = (dirs[0] + TAU - dirs[dirs.len() - 1], dirs[dirs.len() - 1]);
    for w in dirs.windows(2) {
        if w[1] - w[0] > best.0 {
            best = (w[1] - w[0], w[0]);
        }
    }
    best.1 + best.0 / 2.0
}

/// A programmed element projected onto the plane.
struct ProgElem {
    from: (f64, f64),
    to: (f64, f64),
    /// Its points from `from` to `to` (an arc sampled).
    points: Vec<(f64, f64)>,
    /// The element as an arc in the picture's plane.
    arc: Option<Curve>,
    rapid: bool,
    line: u32,
}

fn programmed_group(v: &View, prog: &[ProgElem], alarm_line: Option<u32>) -> Group {
    let mut g = Group::new()
        .set("id", "programmed")
        .set("fill", "none")
        .set("stroke", PROGRAMMED)
        .set("stroke-linecap", "round");
    for e in prog {
        let (from, to) = (v.px(e.from), v.px(e.to));
        if e.arc.is_none() && (from.0 - to.0).hypot(from.1 - to.1) < 1e-3 {
            continue;
        }
        let d = Data::new().move_to((from.0 as f32, from.1 as f32));
        let d = match &e.arc {
            Some(arc) => arc_data(d, v, arc, e.to),
            None => d.line_to((to.0 as f32, to.1 as f32)),
        };
        let mut p = Path::new().set("d", d);
        if alarm_line.is_some_and(|l| e.line > l) {
            // Not prepared: preparation stopped at the alarm.
            p = p.set("opacity", 0.3);
        }
        if e.rapid {
            p = p
                .set("stroke-width", 0.9)
                .set("stroke-dasharray", "3 4")
                .set("stroke-opacity", 0.6);
        } else {
            p = p.set("stroke-width", 1.4);
        }
        g = g.add(p);
    }
    g
}

fn grid(v: &View, plane: Plane, w: f64, h: f64) -> Group {
    // About eight steps along the longer side, but at least two labels along the shorter
    // (a long shaft in a flat frame), and never more than ~24 along the longer.
    let coarse = nice_step(w.max(h) / 8.0);
    let fine = nice_step(w.min(h) / 2.5).max(nice_step(w.max(h) / 24.0));
    let step = coarse.min(fine);
    let mut g = Group::new()
        .set("id", "grid")
        .set("stroke", GRID)
        .set("stroke-width", 1)
        .set("font-size", 10)
        .set("fill", UNCOMP);
    let (u0, v0) = (v.min_u, v.min_v);
    let (u1, v1) = (u0 + w, v0 + h);
    let (x0, y0) = v.px((u0, v0));
    let (x1, y1) = v.px((u1, v1));
    // The frame from the top edge down, whichever way the ordinate is drawn.
    g = g.add(
        Rectangle::new()
            .set("x", rd(x0))
            .set("y", rd(y0.min(y1)))
            .set("width", rd(x1 - x0))
            .set("height", rd((y0 - y1).abs()))
            .set("fill", "none")
            .set("stroke", "#c9cdd2"),
    );
    let mut u = (u0 / step).ceil() * step;
    while u <= u1 {
        let (x, _) = v.px((u, v0));
        g = g
            .add(
                Line::new()
                    .set("x1", rd(x))
                    .set("y1", rd(y1))
                    .set("x2", rd(x))
                    .set("y2", rd(y0)),
            )
            .add(
                Text::new(num(u))
                    .set("x", rd(x))
                    .set("y", rd(y0 + 14.0))
                    .set("text-anchor", "middle")
                    .set("stroke", "none"),
            );
        u += step;
    }
    let mut o = (v0 / step).ceil() * step;
    while o <= v1 {
        let (_, y) = v.px((u0, o));
        g = g
            .add(
                Line::new()
                    .set("x1", rd(x0))
                    .set("y1", rd(y))
                    .set("x2", rd(x1))
                    .set("y2", rd(y)),
            )
            .add(
                Text::new(num(o))
                    .set("x", rd(x0 - 6.0))
                    .set("y", rd(y + 3.5))
                    .set("text-anchor", "end")
                    .set("stroke", "none"),
            );
        o += step;
    }
    g.add(
        Text::new(format!("{} [mm]", AXIS_NAMES[plane.abscissa as usize]))
            .set("x", rd(x1))
            .set("y", rd(y0 + 28.0))
            .set("text-anchor", "end")
            .set("stroke", "none")
            .set("font-size", 11),
    )
    .add(
        Text::new(format!("{} [mm]", AXIS_NAMES[plane.ordinate as usize]))
            .set("x", rd(x0 - 6.0))
            .set("y", rd(y1 - 8.0))
            .set("text-anchor", "end")
            .set("stroke", "none")
            .set("font-size", 11),
    )
}

/// World (plane) → screen px.
struct View {
    min_u: f64,
    min_v: f64,
    scale: f64,
    plot_h: f64,
    /// The ordinate grows downwards (a lathe seen in front of the centre).
    mirrored: bool,
}

impl View {
    fn px(&self, p: (f64, f64)) -> (f64, f64) {
        let v = (p.1 - self.min_v) * self.scale;
        (
            LEFT + (p.0 - self.min_u) * self.scale,
            if self.mirrored {
                TOP + v
            } else {
                TOP + self.plot_h - v
            },
        )
    }
}

#[derive(Default)]
struct Bbox {
    min: (f64, f64),
    max: (f64, f64),
    n: usize,
}

impl Bbox {
    fn add(&mut self, p: (f64, f64)) {
        if !(p.0.is_finite() && p.1.is_finite()) {
            return;
        }
        if self.n == 0 {
            self.min = p;
            self.max = p;
        } else {
            self.min = (self.min.0.min(p.0), self.min.1.min(p.1));
            self.max = (self.max.0.max(p.0), self.max.1.max(p.1));
        }
        self.n += 1;
    }
    fn empty(&self) -> bool {
        self.n == 0
    }
    fn holds(&self, p: (f64, f64)) -> bool {
        self.n > 0
            && (self.min.0..=self.max.0).contains(&p.0)
            && (self.min.1..=self.max.1).contains(&p.1)
    }
    fn size(&self) -> (f64, f64) {
        (self.max.0 - self.min.0, self.max.1 - self.min.1)
    }
}

/// SVG arc commands for a constant-radius arc ending at `to`; a full circle is drawn as two
/// halves.
fn arc_data(d: Data, v: &View, arc: &Curve, to: (f64, f64)) -> Data {
    let &Curve::Arc {
        c0, r0, th0, sweep, ..
    } = arc
    else {
        let (x, y) = v.px(to);
        return d.line_to((x as f32, y as f32));
    };
    let rp = (r0 * v.scale) as f32;
    // The screen's y axis points down: a counter-clockwise arc in the plane has SVG sweep 0
    // (1 where the view is mirrored).
    let flag = if (sweep > 0.0) != v.mirrored {
        0.0
    } else {
        1.0
    };
    let mut d = d;
    let pieces = if sweep.abs() > 0.999 * TAU { 2 } else { 1 };
    for k in 1..=pieces {
        let a = th0 + sweep * k as f64 / pieces as f64;
        let end = if k == pieces {
            to
        } else {
            (c0[0] + r0 * a.cos(), c0[1] + r0 * a.sin())
        };
        let (x, y) = v.px(end);
        let large = if (sweep / pieces as f64).abs() > std::f64::consts::PI {
            1.0
        } else {
            0.0
        };
        d = d.elliptical_arc_to((rp, rp, 0.0, large, flag, x as f32, y as f32));
    }
    d
}

fn role_style(s: &Segment) -> (&'static str, f64, Option<&'static str>) {
    if s.rapid {
        return (UNCOMP, 1.2, Some("5 4"));
    }
    match s.role {
        Role::Contour => (CONTOUR, 2.2, None),
        Role::Approach | Role::Retract => (APPROACH, 2.2, None),
        Role::Corner | Role::Intermediate => (CORNER, 2.2, None),
        Role::Uncompensated => (UNCOMP, 1.4, None),
    }
}

/// 1, 2 or 5 × 10^k, the nearest at or above `raw`.
fn nice_step(raw: f64) -> f64 {
    if !(raw.is_finite() && raw > 0.0) {
        return 1.0;
    }
    let e = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * e)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * e)
}

/// A coordinate for a label: no trailing zeros, at most 3 decimals.
fn num(v: f64) -> String {
    let s = format!("{:.3}", v + 0.0);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// Screen coordinates to 0.01 px: enough for any display, and a readable file.
fn rd(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_steps_are_round() {
        assert_eq!(nice_step(12.0), 20.0);
        assert_eq!(nice_step(4.0), 5.0);
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(100.0), 100.0);
        assert_eq!(num(-0.0), "0");
        assert_eq!(num(12.5), "12.5");
    }
}
