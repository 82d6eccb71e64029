//! The limits on work: loop iterations and function calls, vector lengths and call depth, each
//! checked before the work it bounds.

use qcsg_diag::{FileId, Span};

use crate::codes;

use super::{Evaluator, R};

impl<'a> Evaluator<'a> {
    pub(super) fn tick(&mut self, n: u64, file: FileId, span: Span) -> R<()> {
        self.iterations = self.iterations.saturating_add(n);
        if self.iterations > self.options.max_iterations {
            return Err(self.error(
                codes::ITERATION_LIMIT,
                format!(
                    "more than {} loop iterations and function calls",
                    self.options.max_iterations
                ),
                file,
                span,
            ));
        }
        Ok(())
    }

    pub(super) fn check_len(&mut self, n: u64, file: FileId, span: Span) -> R<()> {
        if n > self.options.max_vector_len {
            return Err(self.error(
                codes::VECTOR_LIMIT,
                format!(
                    "a vector of {n} elements is longer than the limit of {}",
                    self.options.max_vector_len
                ),
                file,
                span,
            ));
        }
        Ok(())
    }

    pub(super) fn enter(&mut self, file: FileId, span: Span) -> R<()> {
        self.depth += 1;
        if self.depth > self.options.max_recursion {
            self.depth -= 1;
            return Err(self.error(
                codes::RECURSION_LIMIT,
                format!("calls nested deeper than {}", self.options.max_recursion),
                file,
                span,
            ));
        }
        Ok(())
    }
}
