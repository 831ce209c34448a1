//! Camera paths for scripted runs (`tracer view SCENE --script FILE`).
//!
//! One command a line; each line is applied and then one frame is rendered. `#` starts a
//! comment. Distances are in scene units, angles in degrees:
//!
//! ```text
//! move D        # forward along C_d (negative: back)
//! strafe D      # right along C_l
//! rise D        # up along C_u
//! yaw DEG       # turn right about the scene's up vector
//! pitch DEG     # turn up about C_l
//! zoom F        # multiply the angle of view by F
//! angle DEG     # set the angle of view
//! reset         # back to the scene's camera
//! set KNOB V    # set a live knob: aa, depth, threshold, precision, threads
//! ```

use super::camera::FlyCamera;
use super::knobs::{self, Knobs};
use std::path::Path;

/// One scripted step.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Move forward, right and up.
    Translate(f64, f64, f64),
    /// Turn right and up, in degrees.
    Turn(f64, f64),
    /// Multiply the angle of view.
    Zoom(f64),
    /// Set the angle of view, in degrees.
    Angle(f64),
    /// Back to the scene's camera.
    Reset,
    /// Set a knob (by its index in [`knobs::KNOBS`]) from text already checked to parse.
    Set(usize, String),
}

impl Step {
    /// Applies the step to the camera and knobs.
    pub fn apply(&self, cam: &mut FlyCamera, k: &mut Knobs) {
        match self {
            Step::Translate(f, r, u) => cam.translate(*f, *r, *u),
            Step::Turn(y, p) => cam.turn(*y, *p),
            Step::Zoom(z) => cam.zoom(*z),
            Step::Angle(a) => cam.set_angle(*a),
            Step::Reset => cam.reset(),
            Step::Set(i, v) => {
                // Checked when parsed; a failure here cannot happen.
                let _ = (knobs::KNOBS[*i].set)(k, v);
            }
        }
    }
}

/// Parses a camera path; errors are one line `FILE:LINE: message`.
pub fn parse(path: &Path, text: &str) -> Result<Vec<Step>, String> {
    let mut steps = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let err = |msg: String| format!("{}:{}: {msg}", path.display(), n + 1);
        let line = line.split('#').next().unwrap_or("");
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some((&cmd, args)) = words.split_first() else {
            continue;
        };
        let num = |i: usize| -> Result<f64, String> {
            let s = args
                .get(i)
                .ok_or_else(|| err(format!("`{cmd}` needs a number")))?;
            s.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| err(format!("`{s}` is not a finite number")))
        };
        let want = match cmd {
            "reset" => 0,
            "set" => 2,
            _ => 1,
        };
        if args.len() != want {
            return Err(err(format!(
                "`{cmd}` takes {want} argument(s), got {}",
                args.len()
            )));
        }
        let step = match cmd {
            "move" => Step::Translate(num(0)?, 0.0, 0.0),
            "strafe" => Step::Translate(0.0, num(0)?, 0.0),
            "rise" => Step::Translate(0.0, 0.0, num(0)?),
            "yaw" => Step::Turn(num(0)?, 0.0),
            "pitch" => Step::Turn(0.0, num(0)?),
            "zoom" => {
                let z = num(0)?;
                if z <= 0.0 {
                    return Err(err(format!("zoom factor must be positive, got {z}")));
                }
                Step::Zoom(z)
            }
            "angle" => Step::Angle(num(0)?),
            "reset" => Step::Reset,
            "set" => {
                let i = knobs::KNOBS
                    .iter()
                    .position(|k| k.name == args[0])
                    .ok_or_else(|| err(format!("unknown knob `{}`", args[0])))?;
                let mut probe = Knobs::default();
                (knobs::KNOBS[i].set)(&mut probe, args[1])
                    .map_err(|m| err(format!("{}: {m}", args[0])))?;
                Step::Set(i, args[1].to_string())
            }
            _ => return Err(err(format!("unknown command `{cmd}`"))),
        };
        steps.push(step);
    }
    if steps.is_empty() {
        return Err(format!("{}: no commands", path.display()));
    }
    Ok(steps)
}

/// Reads and parses a camera path file.
pub fn load(path: &Path) -> Result<Vec<Step>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse(path, &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(text: &str) -> Result<Vec<Step>, String> {
        parse(Path::new("path.txt"), text)
    }

    #[test]
    fn parses_every_command() {
        let s = p(
            "# a path\nmove 1\nstrafe -2 # right\nrise 0.5\nyaw 10\npitch -5\n\
                   zoom 0.5\nangle 30\nreset\nset aa 2\n",
        )
        .unwrap();
        assert_eq!(s.len(), 9);
        assert_eq!(s[1], Step::Translate(0.0, -2.0, 0.0));
        assert_eq!(s[8], Step::Set(0, "2".into()));
    }

    #[test]
    fn errors_name_file_and_line() {
        assert_eq!(
            p("move 1\nfly 2\n").unwrap_err(),
            "path.txt:2: unknown command `fly`"
        );
        assert_eq!(
            p("\nmove x").unwrap_err(),
            "path.txt:2: `x` is not a finite number"
        );
        assert!(p("yaw")
            .unwrap_err()
            .starts_with("path.txt:1: `yaw` takes 1"));
        assert!(p("set aa 99").unwrap_err().starts_with("path.txt:1: aa: "));
        assert!(p("set isa avx2")
            .unwrap_err()
            .contains("unknown knob `isa`"));
        assert!(p("zoom 0").unwrap_err().contains("positive"));
        assert_eq!(p("# nothing\n").unwrap_err(), "path.txt: no commands");
    }
}
