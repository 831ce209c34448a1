//! The checked-in limits (`asm-dumps/bounds.txt`): which kernels are dumped and checked
//! on which targets, the most instructions each may take, and which of the strict rules
//! it is exempt from.
//!
//! One kernel and target per line, `#` starts a comment:
//! ```text
//! # kernel            target      max   allow
//! reflect_f32x3       x86-64-v4   14    -
//! normalize_f32x3     x86-64-v4   40    branch,call
//! ```
//! `allow` is `-` (no exemption: no call, no branch, no stack access, some SIMD) or a
//! comma-separated list of `call`, `branch`, `stack`, `scalar`.

use crate::asm::Analysis;
use std::fmt;

/// Rules a kernel is exempt from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Allow {
    /// May contain `call` (a cold slow path, a library function).
    pub call: bool,
    /// May contain `j*` (a loop, a slow path).
    pub branch: bool,
    /// May read or write the stack.
    pub stack: bool,
    /// May contain no packed SIMD instruction.
    pub scalar: bool,
}

/// The limits for one kernel on one target.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bound {
    /// The probe's symbol.
    pub kernel: String,
    /// The `-C target-cpu` value.
    pub target: String,
    /// The largest accepted instruction count.
    pub max_instructions: usize,
    /// Exemptions from the strict rules.
    pub allow: Allow,
}

/// A line of the bounds file that could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// 1-based line number.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "bounds line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for ParseError {}

/// Parses the bounds file.
///
/// # Errors
/// A line without four fields, a count that is not a number, an unknown exemption, or a
/// kernel listed twice for the same target.
///
/// # Examples
/// ```
/// let b = asm_dumps::bounds::parse("reflect_f32x3 x86-64 20 -  # strict\n").unwrap();
/// assert_eq!(b[0].max_instructions, 20);
/// assert!(!b[0].allow.call);
/// ```
pub fn parse(text: &str) -> Result<Vec<Bound>, ParseError> {
    let mut out: Vec<Bound> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let err = |message: String| ParseError {
            line: n + 1,
            message,
        };
        let fields: Vec<&str> = line.split_whitespace().collect();
        let [kernel, target, max, allow] = fields[..] else {
            return Err(err(format!(
                "expected `kernel target max allow`, found {} fields",
                fields.len()
            )));
        };
        let max_instructions = max
            .parse()
            .map_err(|_| err(format!("`{max}` is not an instruction count")))?;
        let mut a = Allow::default();
        if allow != "-" {
            for rule in allow.split(',') {
                match rule {
                    "call" => a.call = true,
                    "branch" => a.branch = true,
                    "stack" => a.stack = true,
                    "scalar" => a.scalar = true,
                    other => return Err(err(format!("unknown exemption `{other}`"))),
                }
            }
        }
        if out.iter().any(|b| b.kernel == kernel && b.target == target) {
            return Err(err(format!("{kernel} on {target} listed twice")));
        }
        out.push(Bound {
            kernel: kernel.to_string(),
            target: target.to_string(),
            max_instructions,
            allow: a,
        });
    }
    Ok(out)
}

impl Bound {
    /// The rules `a` breaks, one message each; empty if it passes.
    pub fn violations(&self, a: &Analysis) -> Vec<String> {
        let mut v = Vec::new();
        let list = |what: &[String]| {
            let shown: Vec<&str> = what.iter().take(3).map(String::as_str).collect();
            let more = what.len().saturating_sub(3);
            let tail = if more > 0 {
                format!(" and {more} more")
            } else {
                String::new()
            };
            format!("{}{tail}", shown.join("; "))
        };
        if a.instructions > self.max_instructions {
            v.push(format!(
                "{} instructions, more than the bound {}",
                a.instructions, self.max_instructions
            ));
        }
        if !self.allow.call && !a.calls.is_empty() {
            v.push(format!("calls: {}", list(&a.calls)));
        }
        if !self.allow.branch && !a.branches.is_empty() {
            v.push(format!("branches: {}", list(&a.branches)));
        }
        if !self.allow.stack && !a.stack.is_empty() {
            v.push(format!("stack accesses: {}", list(&a.stack)));
        }
        if !self.allow.scalar && a.simd == 0 {
            v.push("no packed SIMD instruction".to_string());
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        let b = parse(
            "# header\n\nreflect_f32x3 x86-64 20 -\nnormalize_f32x3   x86-64-v4  40 branch,call # x\n",
        )
        .unwrap();
        assert_eq!(b.len(), 2);
        assert_eq!(b[1].target, "x86-64-v4");
        assert!(b[1].allow.call && b[1].allow.branch && !b[1].allow.stack);
        assert_eq!(parse("a b c\n").unwrap_err().line, 1);
        assert!(parse("a b x -\n").is_err());
        assert!(parse("a b 1 jump\n").is_err());
        assert!(parse("a b 1 -\na b 2 -\n").is_err());
    }

    #[test]
    fn reports_violations() {
        let strict = &parse("k x86-64 3 -").unwrap()[0];
        let a = Analysis {
            instructions: 4,
            calls: vec!["call\tfmaf".into()],
            branches: vec!["jne\t.LBB_1".into()],
            stack: vec!["push\trbx".into()],
            simd: 0,
            widest: 0,
        };
        assert_eq!(strict.violations(&a).len(), 5);
        let lax = &parse("k x86-64 4 call,branch,stack,scalar").unwrap()[0];
        assert!(lax.violations(&a).is_empty());
    }
}
