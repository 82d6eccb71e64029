//! References and uses: each name reference is recorded once, for the language server, and a
//! definition it reaches (with the assignments it redefines) is marked used.

use qcsg_diag::{FileId, Span};

use crate::{DefId, Namespace, Reference, Target};

use super::{Resolver, VarBinding};

impl<'a> Resolver<'a> {
    pub(super) fn use_binding(&mut self, file: FileId, span: Span, binding: &VarBinding) {
        self.reference(file, span, Namespace::Variable, binding.target);
        if let Some(def) = binding.def {
            self.mark_used(def);
        }
    }

    pub(super) fn reference(
        &mut self,
        file: FileId,
        span: Span,
        namespace: Namespace,
        target: Target,
    ) {
        if self.reference_index.insert((file, span, namespace)) {
            self.references.push(Reference {
                file,
                span,
                namespace,
                target,
            });
        }
    }

    pub(super) fn mark_used(&mut self, def: DefId) {
        if self.enclosing.contains(&def) {
            return;
        }
        let mut next = Some(def);
        while let Some(current) = next {
            match self.used.get_mut(current.0 as usize) {
                Some(flag) if !*flag => *flag = true,
                _ => break,
            }
            next = self
                .definitions
                .get(current.0 as usize)
                .and_then(|d| d.redefines);
        }
    }
}
