//! `--max-memory`: the flag of the size guard ([`subdiv::budget`]) of every
//! command that refines.

use crate::failure::{bad_input, Failure};
use anyhow::anyhow;
use subdiv::budget::{parse_bytes, BudgetError, MemoryBudget};

/// `--max-memory`, shared by the commands that refine.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct MemoryArgs {
    /// Memory budget for refinement, in bytes (suffixes K, M, G, T: powers of 1024;
    /// default ¾ of the memory available to the process). Larger results are refused with exit 2.
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    max_memory: Option<u64>,
}

impl MemoryArgs {
    /// The budget: `--max-memory`, else ¾ of the memory available.
    pub fn budget(&self) -> MemoryBudget {
        MemoryBudget::given_or_available(self.max_memory, "--max-memory")
    }
}

/// A refusal as exit 2, naming the flag that raises the budget.
pub fn refused(e: BudgetError) -> Failure {
    let hint = if matches!(e, BudgetError::OverBudget { .. }) { " or set --max-memory" } else { "" };
    bad_input(anyhow!("{e}{hint}"))
}
