//! Stable diagnostic codes of the GBASIC compiler (documented in `docs/gbasic.md`).
//! E2xxx is the compiler's range: E20xx syntax, E21xx names, E22xx types, E23xx
//! control flow and structure, W2xxx warnings.

/// A token that does not fit the grammar here.
pub const SYNTAX: &str = "E2001";
/// A character that starts no token.
pub const BAD_CHARACTER: &str = "E2002";
/// A number that does not fit (integer beyond 64 bits, float not finite).
pub const BAD_NUMBER: &str = "E2003";
/// A block (`if`, `while`, `do`, `for`) with no closing word.
pub const MISSING_CLOSER: &str = "E2004";
/// A closing word (`endif`, `wend`, `loop`, `next`, `else`) with no open block.
pub const STRAY_CLOSER: &str = "E2005";
/// A keyword where a name is expected.
pub const KEYWORD_AS_NAME: &str = "E2006";
/// `next V` where V is not the innermost loop's variable.
pub const BAD_NEXT: &str = "E2007";
/// Blocks or an expression nested too deeply (more than 100 levels).
pub const TOO_DEEP: &str = "E2008";
/// An expression tree deeper than 256 operators (a long chain `1 + 1 + …` included).
pub const EXPRESSION_TOO_DEEP: &str = "E2009";
/// A lone expression (a debugger's condition or watch) longer than 64 KiB.
pub const EXPRESSION_TOO_LONG: &str = "E2010";

/// A name that is neither declared nor a sensor.
pub const UNDECLARED: &str = "E2101";
/// A name declared twice, or a declaration that reuses a sensor's or built-in's name.
pub const DUPLICATE: &str = "E2102";
/// `goto` to a label that is not defined.
pub const UNDEFINED_LABEL: &str = "E2103";
/// A label defined twice.
pub const DUPLICATE_LABEL: &str = "E2104";
/// Assigning to a read-only sensor (`m_`, `x_`).
pub const READ_ONLY_SENSOR: &str = "E2105";
/// Assigning to a constant, or a name used in the wrong way (an array without an
/// index, a scalar with one, a built-in as a value).
pub const WRONG_KIND: &str = "E2106";

/// Operand or value of the wrong type.
pub const TYPE_MISMATCH: &str = "E2201";
/// A constant index outside the array.
pub const INDEX_OUT_OF_BOUNDS: &str = "E2202";
/// An array size that is not a positive integer.
pub const BAD_ARRAY_SIZE: &str = "E2203";
/// A built-in called with the wrong number of arguments.
pub const BAD_ARGUMENTS: &str = "E2204";
/// A constant expression that divides by zero.
pub const DIVISION_BY_ZERO: &str = "E2205";

/// `exit for|do|while` outside such a loop.
pub const EXIT_OUTSIDE_LOOP: &str = "E2301";
/// The program is too large for GLOC's limits.
pub const TOO_LARGE: &str = "E2302";

/// A store to a factory (`f_`) sensor.
pub const FACTORY_SENSOR: &str = "W2101";
/// A variable that is declared but never used.
pub const UNUSED: &str = "W2102";
/// A `for` loop whose constant step is zero never ends.
pub const ZERO_STEP: &str = "W2301";
/// The worst case per control cycle exceeds the cycle budget.
pub const OVER_BUDGET: &str = "W2302";
