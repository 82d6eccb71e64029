//! "Did you mean" candidates: the names of a namespace visible where a name is missing, handed
//! to the suggestion budget of the check.

use crate::Namespace;
use crate::builtins;
use crate::ty::Ty;

use super::{Resolver, Scope};

impl<'a> Resolver<'a> {
    /// The visible name of `namespace` closest to `name`, for "did you mean".
    pub(super) fn suggest(&mut self, name: &str, namespace: Namespace) -> Option<String> {
        // Gathering the candidates costs too: not for a name that gets no suggestion.
        if !self.suggester.wants(name) {
            return None;
        }
        let mut candidates: Vec<&str> = Vec::new();
        let used: Vec<&Scope> = self
            .used_units()
            .iter()
            .filter_map(|&u| self.units.get(u))
            .map(|u| &u.scope)
            .collect();
        for scope in self.scopes.iter().rev() {
            match namespace {
                Namespace::Variable => candidates.extend(scope.vars.keys().map(String::as_str)),
                Namespace::Function => {
                    candidates.extend(scope.funcs.keys().map(String::as_str));
                    candidates.extend(
                        scope
                            .vars
                            .iter()
                            .filter(|(_, b)| b.ty == Ty::Function)
                            .map(|(k, _)| k.as_str()),
                    );
                }
                Namespace::Module => candidates.extend(scope.modules.keys().map(String::as_str)),
            }
        }
        for scope in used {
            match namespace {
                Namespace::Variable => {}
                Namespace::Function => candidates.extend(scope.funcs.keys().map(String::as_str)),
                Namespace::Module => candidates.extend(scope.modules.keys().map(String::as_str)),
            }
        }
        match namespace {
            Namespace::Variable => candidates.extend(builtins::VARIABLES.iter().map(|v| v.0)),
            Namespace::Function => candidates.extend(builtins::FUNCTIONS.iter().map(|f| f.name)),
            Namespace::Module => candidates.extend(builtins::MODULES.iter().map(|m| m.name)),
        }
        // Scope maps iterate in arbitrary order; the choice among ties does not depend on it.
        self.suggester.closest(name, candidates).map(str::to_string)
    }
}
