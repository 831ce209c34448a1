//! Reading x86-64 assembly as emitted by `rustc --emit asm` in Intel syntax: cutting one
//! function out by its symbol, and classifying its instructions.
//!
//! The checks are deliberately syntactic, so they work with nothing but the compiler:
//! - a *call* is any `call` instruction (a library call such as `fmaf` or `memcpy`
//!   included);
//! - a *branch* is any `j*` instruction (conditional, unconditional, or a tail call);
//! - a *stack access* is an operand that addresses memory through `rsp` or `rbp`, or a
//!   `push`/`pop`: with pointer arguments and a result written through a pointer, a
//!   kernel that touches the stack is spilling;
//! - a *SIMD instruction* is a packed operation (several lanes), not a scalar SSE one
//!   such as `mulss`.

use std::fmt;

/// One function cut out of an assembly file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Function {
    /// The symbol.
    pub name: String,
    /// The body: instructions and local labels, with LLVM's trailing comments, label
    /// numbers made independent of the function's position in the file. Directives
    /// (`.cfi_*`, `.p2align`) and whole-line comments are dropped.
    pub body: Vec<String>,
    /// The constant-pool entries the body refers to (`.LCPI_0:` followed by its data
    /// directives), in file order.
    pub constants: Vec<String>,
}

/// Cuts the function `symbol` out of `asm` (the whole `.s` file).
///
/// The body runs from the line `symbol:` to the `.Lfunc_end` label that closes it.
/// Returns `None` if the symbol is not defined in `asm`.
///
/// # Examples
/// ```
/// let s = "\t.globl\tf\nf:\n\t.cfi_startproc\n\tvaddps\txmm0, xmm0, xmm1\n\tret\n.Lfunc_end0:\n";
/// let f = asm_dumps::asm::extract(s, "f").unwrap();
/// assert_eq!(f.body, ["\tvaddps\txmm0, xmm0, xmm1", "\tret"]);
/// ```
pub fn extract(asm: &str, symbol: &str) -> Option<Function> {
    let lines: Vec<&str> = asm.lines().collect();
    let header = format!("{symbol}:");
    let start = lines.iter().position(|l| l.trim_end() == header)?;
    let mut raw = Vec::new();
    for line in &lines[start + 1..] {
        let t = line.trim();
        if t.starts_with(".Lfunc_end") {
            break;
        }
        if t.is_empty() || t.starts_with('#') {
            continue;
        }
        if t.starts_with('.') && !is_label(t) {
            continue; // a directive
        }
        raw.push(line.trim_end());
    }
    let constants = constants_used(&lines, &raw);
    Some(Function {
        name: symbol.to_string(),
        body: raw.iter().map(|l| normalize_labels(l)).collect(),
        constants,
    })
}

/// Is `t` (trimmed) a label definition such as `.LBB3_2:`?
fn is_label(t: &str) -> bool {
    t.ends_with(':') && !t.contains(char::is_whitespace)
}

/// Rewrites function-local label numbers `.LBB<f>_<k>` and `.LCPI<f>_<k>` to
/// `.LBB_<k>` and `.LCPI_<k>`: `<f>` is the function's position in the file, which
/// changes whenever a probe is added above it.
pub fn normalize_labels(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut rest = line;
    while let Some(pos) = rest.find(".L") {
        out.push_str(&rest[..pos]);
        let tail = &rest[pos..];
        let prefix = ["LBB", "LCPI"]
            .iter()
            .find(|p| tail[1..].starts_with(*p))
            .copied();
        match prefix {
            Some(p) => {
                let digits_start = 1 + p.len();
                let digits = tail[digits_start..]
                    .bytes()
                    .take_while(u8::is_ascii_digit)
                    .count();
                if digits > 0 && tail[digits_start + digits..].starts_with('_') {
                    out.push('.');
                    out.push_str(p);
                    rest = &tail[digits_start + digits..];
                } else {
                    out.push_str(&tail[..digits_start]);
                    rest = &tail[digits_start..];
                }
            }
            None => {
                out.push_str(".L");
                rest = &tail[2..];
            }
        }
    }
    out.push_str(rest);
    out
}

/// The constant-pool blocks whose labels the (raw, not renumbered) body mentions.
fn constants_used(lines: &[&str], body: &[&str]) -> Vec<String> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim();
        if t.starts_with(".LCPI") && t.ends_with(':') {
            let label = t.trim_end_matches(':');
            // `.LCPI3_1` must appear as a whole operand, not as a prefix of `.LCPI3_10`.
            let used = body.iter().any(|l| {
                l.match_indices(label)
                    .any(|(p, _)| !l[p + label.len()..].starts_with(|c: char| c.is_ascii_digit()))
            });
            if used {
                out.push(format!("{}:", normalize_labels(label)));
                i += 1;
                while i < lines.len() {
                    let d = lines[i].trim();
                    let data = [".long", ".quad", ".short", ".byte", ".zero", ".space"]
                        .iter()
                        .any(|k| d.starts_with(k));
                    if !data {
                        break;
                    }
                    out.push(format!("\t{d}"));
                    i += 1;
                }
                continue;
            }
        }
        i += 1;
    }
    out
}

/// Instruction text without LLVM's trailing comment, or `None` for a label line.
pub fn instruction(line: &str) -> Option<&str> {
    let t = line.trim();
    if t.is_empty() || is_label(t) || t.starts_with('#') {
        return None;
    }
    let code = match t.find('#') {
        Some(p) => t[..p].trim_end(),
        None => t,
    };
    Some(code)
}

/// The mnemonic of an instruction (prefixes such as `lock` or `rep` skipped).
pub fn mnemonic(ins: &str) -> &str {
    let mut words = ins.split_whitespace();
    let mut m = words.next().unwrap_or("");
    while matches!(
        m,
        "lock" | "rep" | "repe" | "repz" | "repne" | "repnz" | "notrack"
    ) {
        m = words.next().unwrap_or("");
    }
    m
}

/// Does the instruction operate on several lanes at once?
///
/// Packed arithmetic (`*ps`, `*pd`), packed integer and logic (`p*`, `vp*`), and data
/// movement between lanes or whole vectors (shuffles, broadcasts, blends, inserts,
/// extracts, full-register moves) count; scalar SSE (`*ss`, `*sd`), `movd`/`movq` and
/// `vzeroupper` do not.
pub fn is_packed_simd(ins: &str) -> bool {
    let m = mnemonic(ins);
    let base = m.strip_prefix('v').unwrap_or(m);
    let regs = ins.contains("xmm") || ins.contains("ymm") || ins.contains("zmm");
    if m.starts_with("push") || m.starts_with("pop") || m == "vzeroupper" {
        return false;
    }
    if ins.contains("ymm") || ins.contains("zmm") {
        return true;
    }
    if !regs {
        return false;
    }
    let lane_movement = [
        "broadcast",
        "shuf",
        "unpck",
        "perm",
        "insert",
        "extract",
        "blend",
    ]
    .iter()
    .any(|k| base.contains(k));
    lane_movement
        || base.ends_with("ps")
        || base.ends_with("pd")
        || base.starts_with('p')
        || base.starts_with("movdq")
}

/// Does the instruction read or write the stack (`[rsp ...]`, `[rbp ...]`, push, pop)?
pub fn touches_stack(ins: &str) -> bool {
    let m = mnemonic(ins);
    if m.starts_with("push") || m.starts_with("pop") {
        return true;
    }
    ins.split('[')
        .skip(1)
        .any(|addr| addr.trim_start().starts_with("rsp") || addr.trim_start().starts_with("rbp"))
}

/// The properties of one function body that the checks look at.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Analysis {
    /// Number of instructions (labels and directives excluded, `ret` included).
    pub instructions: usize,
    /// The `call` instructions.
    pub calls: Vec<String>,
    /// The `j*` instructions.
    pub branches: Vec<String>,
    /// The instructions that read or write the stack.
    pub stack: Vec<String>,
    /// Number of packed SIMD instructions.
    pub simd: usize,
    /// Widest vector register used: 0 (none), 128, 256 or 512 bits.
    pub widest: u32,
}

impl Analysis {
    /// Classifies every instruction of `body`.
    pub fn of(body: &[String]) -> Self {
        let mut a = Self::default();
        for line in body {
            let Some(ins) = instruction(line) else {
                continue;
            };
            a.instructions += 1;
            let m = mnemonic(ins);
            if m.starts_with("call") {
                a.calls.push(ins.to_string());
            }
            if m.starts_with('j') {
                a.branches.push(ins.to_string());
            }
            if touches_stack(ins) {
                a.stack.push(ins.to_string());
            }
            if is_packed_simd(ins) {
                a.simd += 1;
            }
            let width = if ins.contains("zmm") {
                512
            } else if ins.contains("ymm") {
                256
            } else if ins.contains("xmm") {
                128
            } else {
                0
            };
            a.widest = a.widest.max(width);
        }
        a
    }
}

impl fmt::Display for Analysis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} instructions, {} SIMD, widest {} bits, {} calls, {} branches, {} stack accesses",
            self.instructions,
            self.simd,
            self.widest,
            self.calls.len(),
            self.branches.len(),
            self.stack.len()
        )
    }
}

/// The instruction lines of a body, comments stripped: what drift is judged on.
pub fn comparable(lines: &[String]) -> Vec<String> {
    lines
        .iter()
        .map(|l| match instruction(l) {
            Some(ins) => ins.split_whitespace().collect::<Vec<_>>().join(" "),
            None => l.trim().to_string(),
        })
        .collect()
}

/// A short description of how `new` differs from `old`: line counts, lines removed and
/// added (from a longest-common-subsequence alignment), at most `max_lines` of each.
/// Returns `None` if they are equal.
pub fn diff_summary(old: &[String], new: &[String], max_lines: usize) -> Option<String> {
    if old == new {
        return None;
    }
    let (n, m) = (old.len(), new.len());
    // lcs[i][j]: length of the LCS of old[i..] and new[j..].
    let mut lcs = vec![vec![0u32; m + 1]; n + 1];
    for i in (0..n).rev() {
        for j in (0..m).rev() {
            lcs[i][j] = if old[i] == new[j] {
                lcs[i + 1][j + 1] + 1
            } else {
                lcs[i + 1][j].max(lcs[i][j + 1])
            };
        }
    }
    let (mut removed, mut added) = (Vec::new(), Vec::new());
    let (mut i, mut j) = (0, 0);
    while i < n || j < m {
        if i < n && j < m && old[i] == new[j] {
            i += 1;
            j += 1;
        } else if j < m && (i == n || lcs[i][j + 1] >= lcs[i + 1][j]) {
            added.push(new[j].as_str());
            j += 1;
        } else {
            removed.push(old[i].as_str());
            i += 1;
        }
    }
    let mut s = format!(
        "{} -> {} lines, {} removed, {} added",
        n,
        m,
        removed.len(),
        added.len()
    );
    for l in removed.iter().take(max_lines) {
        s.push_str(&format!("\n      - {l}"));
    }
    if removed.len() > max_lines {
        s.push_str(&format!("\n      - ... {} more", removed.len() - max_lines));
    }
    for l in added.iter().take(max_lines) {
        s.push_str(&format!("\n      + {l}"));
    }
    if added.len() > max_lines {
        s.push_str(&format!("\n      + ... {} more", added.len() - max_lines));
    }
    Some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SAMPLE: &str = "\
\t.section\t.rodata.cst4,\"aM\",@progbits,4
\t.p2align\t2, 0x0
.LCPI12_0:
\t.long\t0x40000000
.LCPI11_0:
\t.long\t0x3f800000
\t.section\t.text.k,\"ax\",@progbits
\t.globl\tk
\t.p2align\t4
\t.type\tk,@function
k:
\t.cfi_startproc
# %bb.0:
\tvmovups\txmm0, xmmword ptr [rdi]
\tvmulps\txmm0, xmm0, dword ptr [rip + .LCPI12_0]{1to4}  # foo
.LBB12_1:
\tvmovss\tdword ptr [rsp - 4], xmm0
\tjne\t.LBB12_1
\tcall\tqword ptr [rip + fmaf@GOTPCREL]
\tret
.Lfunc_end12:
\t.size\tk, .Lfunc_end12-k
\t.cfi_endproc
other:
\tnop
";

    #[test]
    fn extracts_body_and_constants() {
        let f = extract(SAMPLE, "k").unwrap();
        assert_eq!(f.body.len(), 7);
        assert_eq!(f.body[0], "\tvmovups\txmm0, xmmword ptr [rdi]");
        assert_eq!(f.body[2], ".LBB_1:");
        assert_eq!(f.body[4], "\tjne\t.LBB_1");
        assert!(f.body[1].contains("[rip + .LCPI_0]"));
        assert_eq!(f.constants, [".LCPI_0:", "\t.long\t0x40000000"]);
        assert!(extract(SAMPLE, "missing").is_none());
        // A symbol that is a prefix of another is not confused with it.
        assert!(extract(SAMPLE, "ot").is_none());
    }

    #[test]
    fn classifies() {
        let f = extract(SAMPLE, "k").unwrap();
        let a = Analysis::of(&f.body);
        assert_eq!(a.instructions, 6);
        assert_eq!(a.calls.len(), 1);
        assert_eq!(a.branches, ["jne\t.LBB_1"]);
        assert_eq!(a.stack.len(), 1);
        assert_eq!(a.simd, 2);
        assert_eq!(a.widest, 128);
    }

    #[test]
    fn packed_versus_scalar() {
        for packed in [
            "vmulps\tzmm0, zmm1, zmm2",
            "mulps\txmm0, xmm1",
            "vfmadd213ps\tymm0, ymm1, ymm2",
            "vbroadcastss\txmm0, xmm1",
            "vshufps\txmm0, xmm0, xmm0, 85",
            "vpermilps\txmm1, xmm0, 170",
            "vinsertps\txmm0, xmm0, dword ptr [rsi + 8], 32",
            "pxor\txmm0, xmm0",
            "vmovaps\txmm1, xmm0",
            "vmovdqu64\tzmmword ptr [rdx], zmm0",
            "movlhps\txmm0, xmm1",
        ] {
            assert!(is_packed_simd(packed), "{packed}");
        }
        for scalar in [
            "vmulss\txmm0, xmm1, xmm2",
            "mulsd\txmm0, xmm1",
            "vfmadd213ss\txmm0, xmm1, xmm2",
            "movss\tdword ptr [rdx + 8], xmm0",
            "vmovd\teax, xmm0",
            "vzeroupper",
            "ret",
            "push\trbx",
            "mov\trax, qword ptr [rdi]",
        ] {
            assert!(!is_packed_simd(scalar), "{scalar}");
        }
    }

    #[test]
    fn stack_accesses() {
        assert!(touches_stack("vmovaps\txmmword ptr [rsp + 16], xmm6"));
        assert!(touches_stack("mov\trax, qword ptr [rbp - 8]"));
        assert!(touches_stack("push\trbx"));
        assert!(!touches_stack("vmovups\txmm0, xmmword ptr [rdi + rsp]"));
        assert!(!touches_stack("sub\trsp, 40"));
        assert!(!touches_stack("vmovups\txmm0, xmmword ptr [rsi]"));
    }

    #[test]
    fn labels_are_renumbered() {
        assert_eq!(normalize_labels("\tjne\t.LBB12_3"), "\tjne\t.LBB_3");
        assert_eq!(
            normalize_labels("[rip + .LCPI7_10] .Ltmp3 .LBB .L"),
            "[rip + .LCPI_10] .Ltmp3 .LBB .L"
        );
    }

    #[test]
    fn diff() {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert!(diff_summary(&s(&["a", "b"]), &s(&["a", "b"]), 5).is_none());
        let d = diff_summary(&s(&["a", "b", "c"]), &s(&["a", "x", "c", "d"]), 5).unwrap();
        assert!(d.starts_with("3 -> 4 lines, 1 removed, 2 added"), "{d}");
        assert!(d.contains("- b") && d.contains("+ x") && d.contains("+ d"));
        assert_eq!(
            comparable(&s(&["\tvaddps\txmm0, xmm1  # c", ".LBB_1:"])),
            ["vaddps xmm0, xmm1", ".LBB_1:"]
        );
    }
}

/// A call (or tail jump) to a `core::arch` intrinsic found in emitted assembly.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct IntrinsicCall {
    /// The function containing the call (mangled symbol).
    pub caller: String,
    /// The intrinsic called (mangled symbol).
    pub callee: String,
}

/// Every `call` or `jmp` to a function of `core::arch` (`core_arch` in the mangled
/// name) in an `--emit asm` file, with the function it sits in.
///
/// An intrinsic is a function with `#[target_feature]`: inlined into code built with
/// that feature it is one instruction, but code built without it (a closure or helper
/// the compiler left out of line from a `#[target_feature]` entry point) can only call
/// it, so every vector operation becomes a function call.
///
/// # Examples
/// ```
/// let s = "f:\n\tcall\t_ZN4core9core_arch3x863avx13_mm256_mul_ps17h0123456789abcdefE\n\
///          \tret\n.Lfunc_end0:\ng:\n\tcall\tmemcpy@PLT\n\tret\n";
/// let calls = asm_dumps::asm::intrinsic_calls(s);
/// assert_eq!(calls.len(), 1);
/// assert_eq!(calls[0].caller, "f");
/// assert!(calls[0].callee.contains("_mm256_mul_ps"));
/// ```
pub fn intrinsic_calls(asm: &str) -> Vec<IntrinsicCall> {
    let mut out = Vec::new();
    let mut caller = "";
    for line in asm.lines() {
        let t = line.trim();
        if is_label(t) && !t.starts_with(".L") {
            caller = t.trim_end_matches(':');
            continue;
        }
        let Some(ins) = instruction(line) else {
            continue;
        };
        if !matches!(mnemonic(ins), "call" | "jmp") {
            continue;
        }
        if let Some(callee) = ins.split_whitespace().last() {
            if callee.contains("core_arch") {
                out.push(IntrinsicCall {
                    caller: caller.to_string(),
                    callee: callee.to_string(),
                });
            }
        }
    }
    out
}
