//! BVH files (Biovision Hierarchy): a HIERARCHY of joints (name, OFFSET, CHANNELS, children,
//! End Sites) and a MOTION section (`Frames:`, `Frame Time:`, one line of channel values per
//! frame). Any channel layout is read (3 rotations, or 3 positions and 3 rotations per joint,
//! in any order); every fault is reported with its line before any frame is used: a file cut
//! short, a value that is not a finite number, a frame time ≤ 0, a frame whose value count is
//! not the hierarchy's channel count.

use crate::error::{MocapError, Result};
use nalgebra::Vector3;
use std::path::Path;

/// One degree of freedom of a joint, as the CHANNELS line names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    Xposition,
    Yposition,
    Zposition,
    Xrotation,
    Yrotation,
    Zrotation,
}

impl Channel {
    fn parse(word: &str) -> Option<Channel> {
        Some(match word.to_ascii_lowercase().as_str() {
            "xposition" => Channel::Xposition,
            "yposition" => Channel::Yposition,
            "zposition" => Channel::Zposition,
            "xrotation" => Channel::Xrotation,
            "yrotation" => Channel::Yrotation,
            "zrotation" => Channel::Zrotation,
            _ => return None,
        })
    }

    /// The axis (0 x, 1 y, 2 z) and whether it is a rotation.
    pub fn axis(self) -> (usize, bool) {
        match self {
            Channel::Xposition => (0, false),
            Channel::Yposition => (1, false),
            Channel::Zposition => (2, false),
            Channel::Xrotation => (0, true),
            Channel::Yrotation => (1, true),
            Channel::Zrotation => (2, true),
        }
    }
}

/// A joint of the hierarchy.
#[derive(Clone, Debug, PartialEq)]
pub struct BvhJoint {
    pub name: String,
    /// Its parent's index (None: the root).
    pub parent: Option<usize>,
    /// Its origin in its parent's frame, at rest (file units).
    pub offset: Vector3<f64>,
    pub channels: Vec<Channel>,
    /// Index of its first channel in a frame's values.
    pub first_channel: usize,
}

/// A BVH file: its hierarchy and frames.
#[derive(Clone, Debug, PartialEq)]
pub struct Bvh {
    /// Joints in file order (a parent before its children).
    pub joints: Vec<BvhJoint>,
    /// Channel values per frame.
    pub channels: usize,
    /// Seconds between frames.
    pub frame_time: f64,
    /// Frame values, frame after frame (`frames × channels`).
    pub values: Vec<f64>,
}

impl Bvh {
    /// Reads the BVH file at `path`.
    pub fn read(path: &Path) -> Result<Bvh> {
        let text = std::fs::read_to_string(path).map_err(|e| MocapError::Io {
            file: path.display().to_string(),
            message: e.to_string(),
        })?;
        Bvh::parse(&text, &path.display().to_string())
    }

    /// Parses a BVH file's text (`name` is how errors name it).
    pub fn parse(text: &str, name: &str) -> Result<Bvh> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut reader = Reader::new(text, name);
        let (joints, channels) = reader.hierarchy()?;
        let (frame_time, values) = reader.motion(channels)?;
        Ok(Bvh {
            joints,
            channels,
            frame_time,
            values,
        })
    }

    /// Parses the HIERARCHY alone (a live stream's skeleton: its frames come over the wire).
    pub fn parse_hierarchy(text: &str, name: &str) -> Result<Bvh> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut reader = Reader::new(text, name);
        let (joints, channels) = reader.hierarchy()?;
        Ok(Bvh {
            joints,
            channels,
            frame_time: f64::NAN,
            values: Vec::new(),
        })
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.values.len().checked_div(self.channels).unwrap_or(0)
    }

    /// Frame `k`'s channel values.
    pub fn frame(&self, k: usize) -> &[f64] {
        &self.values[k * self.channels..(k + 1) * self.channels]
    }

    /// The index of the joint named `name`.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}

/// Tokens with their line numbers.
struct Reader<'a> {
    name: &'a str,
    lines: Vec<(usize, &'a str)>,
    /// Current line (index into `lines`) and token within it.
    line: usize,
    tokens: Vec<&'a str>,
    token: usize,
    /// Joints open (nesting depth).
    depth: usize,
}

/// Deepest nesting of joints read (a human skeleton has about ten levels).
const MAX_DEPTH: usize = 256;

impl<'a> Reader<'a> {
    fn new(text: &'a str, name: &'a str) -> Reader<'a> {
        let lines: Vec<(usize, &str)> = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l))
            .filter(|(_, l)| !l.trim().is_empty())
            .collect();
        let tokens = lines
            .first()
            .map_or(Vec::new(), |(_, l)| l.split_whitespace().collect());
        Reader {
            name,
            lines,
            line: 0,
            tokens,
            token: 0,
            depth: 0,
        }
    }

    fn line_number(&self) -> usize {
        self.lines
            .get(self.line)
            .or(self.lines.last())
            .map_or(1, |(n, _)| *n)
    }

    fn error<T>(&self, message: impl Into<String>) -> Result<T> {
        Err(MocapError::Bvh {
            file: self.name.to_string(),
            line: self.line_number(),
            message: message.into(),
        })
    }

    /// The next token of the current line, if any.
    fn next_on_line(&mut self) -> Option<&'a str> {
        let t = self.tokens.get(self.token).copied()?;
        self.token += 1;
        Some(t)
    }

    /// The next token, or None at the end of the text.
    fn next(&mut self) -> Option<&'a str> {
        while self.token >= self.tokens.len() {
            self.line += 1;
            let (_, l) = self.lines.get(self.line)?;
            self.tokens = l.split_whitespace().collect();
            self.token = 0;
        }
        self.token += 1;
        Some(self.tokens[self.token - 1])
    }

    fn expect_token(&mut self, what: &str) -> Result<&'a str> {
        match self.next() {
            Some(t) => Ok(t),
            None => self.error(format!(
                "the file ends where {what} was expected (cut short?)"
            )),
        }
    }

    fn number(&mut self, what: &str) -> Result<f64> {
        let t = self.expect_token(what)?;
        match t.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => self.error(format!("{what}: '{t}' is not a finite number")),
        }
    }

    fn hierarchy(&mut self) -> Result<(Vec<BvhJoint>, usize)> {
        if self.expect_token("HIERARCHY")? != "HIERARCHY" {
            return self.error("a BVH file starts with HIERARCHY");
        }
        if self.expect_token("ROOT")? != "ROOT" {
            return self.error("HIERARCHY must be followed by ROOT");
        }
        let mut joints = Vec::new();
        let mut channels = 0;
        self.joint(None, &mut joints, &mut channels)?;
        if joints.iter().all(|j| j.channels.is_empty()) {
            return self.error("the hierarchy has no channels");
        }
        Ok((joints, channels))
    }

    /// A ROOT or JOINT block (its keyword already read).
    fn joint(
        &mut self,
        parent: Option<usize>,
        joints: &mut Vec<BvhJoint>,
        channels: &mut usize,
    ) -> Result<()> {
        if self.depth >= MAX_DEPTH {
            return self.error(format!("joints nested deeper than {MAX_DEPTH}"));
        }
        self.depth += 1;
        let r = self.joint_body(parent, joints, channels);
        self.depth -= 1;
        r
    }

    fn joint_body(
        &mut self,
        parent: Option<usize>,
        joints: &mut Vec<BvhJoint>,
        channels: &mut usize,
    ) -> Result<()> {
        let name = self.expect_token("a joint name")?.to_string();
        if joints.iter().any(|j: &BvhJoint| j.name == name) {
            return self.error(format!("joint '{name}' appears twice"));
        }
        if self.expect_token("{")? != "{" {
            return self.error(format!("joint '{name}': '{{' expected"));
        }
        let index = joints.len();
        joints.push(BvhJoint {
            name: name.clone(),
            parent,
            offset: Vector3::zeros(),
            channels: Vec::new(),
            first_channel: *channels,
        });
        loop {
            match self.expect_token(&format!("the end of joint '{name}'"))? {
                "OFFSET" => {
                    let mut o = Vector3::zeros();
                    for k in 0..3 {
                        o[k] = self.number(&format!("joint '{name}' OFFSET"))?;
                    }
                    joints[index].offset = o;
                }
                "CHANNELS" => {
                    let t = self.expect_token("a channel count")?;
                    let Ok(n) = t.parse::<usize>() else {
                        return self.error(format!(
                            "joint '{name}': CHANNELS count '{t}' is not a number"
                        ));
                    };
                    if n > 6 {
                        return self.error(format!("joint '{name}': {n} channels (at most 6)"));
                    }
                    let mut list = Vec::with_capacity(n);
                    for _ in 0..n {
                        let w = self.expect_token("a channel name")?;
                        match Channel::parse(w) {
                            Some(c) if !list.contains(&c) => list.push(c),
                            Some(_) => {
                                return self
                                    .error(format!("joint '{name}': channel {w} appears twice"))
                            }
                            None => {
                                return self.error(format!(
                                    "joint '{name}': '{w}' is not a channel (Xposition … Zrotation)"
                                ))
                            }
                        }
                    }
                    if !joints[index].channels.is_empty() {
                        return self.error(format!("joint '{name}': CHANNELS given twice"));
                    }
                    joints[index].first_channel = *channels;
                    *channels += n;
                    joints[index].channels = list;
                }
                "JOINT" => self.joint(Some(index), joints, channels)?,
                "End" => {
                    self.expect_token("Site")?;
                    self.end_site()?;
                }
                "}" => return Ok(()),
                other => {
                    return self.error(format!("joint '{name}': unexpected '{other}'"));
                }
            }
        }
    }

    fn end_site(&mut self) -> Result<()> {
        if self.expect_token("{")? != "{" {
            return self.error("End Site: '{' expected");
        }
        loop {
            match self.expect_token("the end of an End Site")? {
                "OFFSET" => {
                    for _ in 0..3 {
                        self.number("End Site OFFSET")?;
                    }
                }
                "}" => return Ok(()),
                other => return self.error(format!("End Site: unexpected '{other}'")),
            }
        }
    }

    fn motion(&mut self, channels: usize) -> Result<(f64, Vec<f64>)> {
        if self.expect_token("MOTION")? != "MOTION" {
            return self.error("MOTION expected after the hierarchy");
        }
        if self.expect_token("Frames:")? != "Frames:" {
            return self.error("'Frames:' expected after MOTION");
        }
        let t = self.expect_token("the frame count")?;
        let Ok(frames) = t.parse::<usize>() else {
            return self.error(format!("frame count '{t}' is not a whole number"));
        };
        if frames == 0 {
            return self.error("the file holds no frame (Frames: 0)");
        }
        if self.expect_token("Frame")? != "Frame" || self.expect_token("Time:")? != "Time:" {
            return self.error("'Frame Time:' expected after the frame count");
        }
        let frame_time = self.number("Frame Time")?;
        if frame_time <= 0.0 {
            return self.error(format!("Frame Time {frame_time} s: must be > 0"));
        }
        if let Some(extra) = self.next_on_line() {
            return self.error(format!("'{extra}' after the frame time (one frame a line)"));
        }
        // A count the file cannot hold reserves no more than its lines.
        let room = frames.min(self.lines.len().saturating_sub(self.line + 1));
        let mut values = Vec::with_capacity(channels.saturating_mul(room));
        for k in 0..frames {
            self.line += 1;
            let Some((_, line)) = self.lines.get(self.line) else {
                self.line -= 1;
                return self.error(format!(
                    "the file ends after {k} of the {frames} frames it declares (cut short?)"
                ));
            };
            let before = values.len();
            for t in line.split_whitespace() {
                match t.parse::<f64>() {
                    Ok(v) if v.is_finite() => values.push(v),
                    _ => return self.error(format!("frame {k}: '{t}' is not a finite number")),
                }
            }
            let n = values.len() - before;
            if n != channels {
                return self.error(format!(
                    "frame {k} has {n} values where the hierarchy has {channels} channels"
                ));
            }
        }
        if self.line + 1 < self.lines.len() {
            self.line += 1;
            return self.error(format!("more lines than the {frames} frames declared"));
        }
        Ok((frame_time, values))
    }
}
