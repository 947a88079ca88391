//! Keys of `corps teleop`: the key map (seed 002 §4.14, REP-103 signs) and key scripts
//! (`--keys FILE`: one `time key` per line).

use anyhow::{bail, Context, Result};
use corps_scenario::teleop::PadAction;
use std::path::Path;

/// What a key does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyAction {
    Pad(PadAction),
    Quit,
}

/// The key map: `i`/`k` forward/backward, `j`/`l` left/right, `u`/`o` turn left/right
/// (counter-clockwise/clockwise), `d`/`s` faster/slower, space stop, `q` quit (seed 002 §4.14's
/// script, its sideways and turning signs put to REP-103).
pub fn action(key: char) -> Option<KeyAction> {
    use PadAction::*;
    Some(match key.to_ascii_lowercase() {
        'i' => KeyAction::Pad(Forward),
        'k' => KeyAction::Pad(Backward),
        'j' => KeyAction::Pad(Left),
        'l' => KeyAction::Pad(Right),
        'u' => KeyAction::Pad(TurnLeft),
        'o' => KeyAction::Pad(TurnRight),
        'd' => KeyAction::Pad(Faster),
        's' => KeyAction::Pad(Slower),
        ' ' => KeyAction::Pad(Stop),
        'q' => KeyAction::Quit,
        _ => return None,
    })
}

/// The help line of the key map.
pub const HELP: &str = "i/k forward/back  j/l left/right  u/o turn left/right  d/s faster/slower  \
                        space stop  q quit";

/// A key pressed at a time (s after the controller takes over).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimedKey {
    pub t: f64,
    pub action: KeyAction,
}

/// Reads a key script: one `time key` per line (`time` in seconds after the handover, times
/// non-decreasing; `key` a key of the map, `space` for the space bar); blank lines and `#`
/// comments are skipped.
pub fn read_script(path: &Path) -> Result<Vec<TimedKey>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("--keys: reading {}", path.display()))?;
    parse_script(&text).with_context(|| format!("--keys: {}", path.display()))
}

/// Parses the text of a key script ([`read_script`]).
pub fn parse_script(text: &str) -> Result<Vec<TimedKey>> {
    let mut keys = Vec::new();
    let mut last = 0.0;
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let at = || format!("line {}", n + 1);
        let mut fields = line.split_whitespace();
        let (Some(time), Some(key), None) = (fields.next(), fields.next(), fields.next()) else {
            bail!("{}: expected `time key`, found {line:?}", at());
        };
        let t: f64 = time
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite() && *t >= 0.0)
            .with_context(|| format!("{}: time {time:?} is not a number ≥ 0", at()))?;
        if t < last {
            bail!("{}: time {t} s is before the previous key's {last} s", at());
        }
        last = t;
        let c = match key {
            "space" => ' ',
            k if k.chars().count() == 1 => k.chars().next().unwrap_or(' '),
            _ => bail!(
                "{}: unknown key {key:?} ({HELP}; `space` for the space bar)",
                at()
            ),
        };
        let Some(action) = action(c) else {
            bail!("{}: unknown key {key:?} ({HELP})", at());
        };
        keys.push(TimedKey { t, action });
    }
    Ok(keys)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_script_reads_and_bad_lines_name_their_line() {
        let keys = parse_script("# walk\n0.5 i\n\n1.0 space  # stop\n2 q\n").unwrap();
        assert_eq!(keys.len(), 3);
        assert_eq!(keys[1].action, KeyAction::Pad(PadAction::Stop));
        assert_eq!(
            keys[2],
            TimedKey {
                t: 2.0,
                action: KeyAction::Quit
            }
        );
        for (text, expected) in [
            ("1 i\n0.5 k", "line 2: time 0.5 s is before"),
            ("x i", "line 1: time \"x\""),
            ("nan i", "line 1: time \"nan\""),
            ("1 z", "line 1: unknown key \"z\""),
            ("1", "line 1: expected `time key`"),
            ("1 i k", "line 1: expected `time key`"),
        ] {
            let e = format!("{:#}", parse_script(text).unwrap_err());
            assert!(e.contains(expected), "{text:?}: {e}");
        }
    }
}
