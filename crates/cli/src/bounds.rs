//! Upper bounds of the counts the command line takes (poses, starts, generations, modes, grid
//! nodes), checked when the option is parsed, before anything is allocated: a count beyond what
//! memory and time allow is bad input (exit 2) naming the largest allowed (docs/limits.md).

/// A whole number from `MIN` to `MAX` (a clap value parser: `value_parser = bounds::count::<1, 1000>`).
pub fn count<const MIN: usize, const MAX: usize>(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (MIN..=MAX).contains(&n) => Ok(n),
        Ok(n) if n > MAX => Err(format!("{n} is more than the {MAX} allowed (a bound on memory and time, docs/limits.md)")),
        _ => Err(format!("`{text}`: expected a whole number of at least {MIN} and at most {MAX}")),
    }
}

/// Most poses, records or readings a command generates (design trajectory, optimal counts).
pub const MAX_POSES: usize = 1_000_000;
/// Most random starts, generations or iterations of a search.
pub const MAX_ITERATIONS: usize = 100_000;
/// Most modes of a thermal modal analysis.
pub const MAX_MODES: usize = 1000;
