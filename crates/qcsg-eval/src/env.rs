//! Scopes: lexical for ordinary names, dynamic for `$`-variables.
//!
//! A [`Frame`] holds the variables, functions and modules one scope defines. Ordinary names are
//! looked up along the *lexical* chain (where the code is written); `$`-variables along the
//! *dynamic* chain (the scopes active when the frame was entered: callers, module instances),
//! which is how OpenSCAD lets `$fn` set at a call reach everything the callee instantiates.

use std::cell::RefCell;
use std::collections::HashMap;
use std::rc::Rc;

use qcsg_diag::FileId;
use qcsg_syntax::ast::{Expr, Param, Stmt};

use crate::value::Value;

/// A user function (`function f(…) = …;`) or module (`module m(…) …`) and its defining scope.
#[derive(Debug)]
pub struct Callable<'a, B: ?Sized> {
    /// Its parameters.
    pub params: &'a [Param],
    /// Its body.
    pub body: &'a B,
    /// The scope it is defined in.
    pub env: Rc<Frame<'a>>,
    /// The file its text is in.
    pub file: FileId,
}

/// A user function definition.
pub type FunctionDef<'a> = Callable<'a, Expr>;
/// A user module definition.
pub type ModuleDef<'a> = Callable<'a, Stmt>;

/// The children of a module instance: the statements written after the instantiation and the
/// scope they are written in.
#[derive(Debug)]
pub struct Children<'a> {
    /// Assignments of the children's scope `(name, value, file)`, evaluated each time children
    /// are instantiated.
    pub assignments: Vec<(&'a str, &'a Expr, FileId)>,
    /// Definitions of the children's scope.
    pub definitions: Vec<(FileId, &'a Stmt)>,
    /// The instantiations (what `children(i)` indexes).
    pub items: Vec<(FileId, &'a Stmt)>,
    /// The scope the instantiation is written in.
    pub env: Rc<Frame<'a>>,
}

/// Scopes with more variables than this look names up through a hash index; smaller ones (the
/// frames of most calls) scan their list, which costs less than building the index.
const INDEX_FROM: usize = 16;

/// The variables of one scope: each name once, in order of first assignment.
#[derive(Debug, Default)]
struct Vars<'a> {
    list: Vec<(&'a str, Value<'a>)>,
    /// Position in `list` of each name, once `list` has grown past [`INDEX_FROM`].
    index: HashMap<&'a str, usize>,
}

impl<'a> Vars<'a> {
    fn position(&self, name: &str) -> Option<usize> {
        if self.list.len() > INDEX_FROM {
            self.index.get(name).copied()
        } else {
            self.list.iter().position(|(n, _)| *n == name)
        }
    }

    fn set(&mut self, name: &'a str, value: Value<'a>) {
        match self.position(name) {
            Some(i) => self.list[i].1 = value,
            None => {
                self.list.push((name, value));
                if self.list.len() > INDEX_FROM {
                    if self.index.is_empty() {
                        self.index = self
                            .list
                            .iter()
                            .enumerate()
                            .map(|(i, (n, _))| (*n, i))
                            .collect();
                    } else {
                        self.index.insert(name, self.list.len() - 1);
                    }
                }
            }
        }
    }
}

/// One scope.
#[derive(Debug, Default)]
pub struct Frame<'a> {
    vars: RefCell<Vars<'a>>,
    functions: RefCell<Vec<(&'a str, Rc<FunctionDef<'a>>)>>,
    modules: RefCell<Vec<(&'a str, Rc<ModuleDef<'a>>)>>,
    /// The enclosing scope in the source.
    pub lexical: Option<Rc<Frame<'a>>>,
    /// The scope that was active when this one was entered.
    pub dynamic: Option<Rc<Frame<'a>>>,
    /// For a module instance's frame: its children.
    pub children: Option<Rc<Children<'a>>>,
}

impl<'a> Frame<'a> {
    /// A root scope.
    pub fn root() -> Rc<Self> {
        Rc::new(Self::default())
    }

    /// A scope nested in `lexical`, entered from `dynamic`.
    pub fn child(lexical: &Rc<Frame<'a>>, dynamic: &Rc<Frame<'a>>) -> Rc<Self> {
        Rc::new(Self {
            lexical: Some(lexical.clone()),
            dynamic: Some(dynamic.clone()),
            ..Self::default()
        })
    }

    /// A block nested in `parent` (lexically and dynamically).
    pub fn nested(parent: &Rc<Frame<'a>>) -> Rc<Self> {
        Self::child(parent, parent)
    }

    /// A module instance's scope.
    pub fn module_instance(
        lexical: &Rc<Frame<'a>>,
        dynamic: &Rc<Frame<'a>>,
        children: Rc<Children<'a>>,
    ) -> Rc<Self> {
        Rc::new(Self {
            lexical: Some(lexical.clone()),
            dynamic: Some(dynamic.clone()),
            children: Some(children),
            ..Self::default()
        })
    }

    /// Sets (or replaces) a variable of this scope.
    pub fn set(&self, name: &'a str, value: Value<'a>) {
        self.vars.borrow_mut().set(name, value);
    }

    /// The variables of this scope, in assignment order.
    pub fn locals(&self) -> Vec<(&'a str, Value<'a>)> {
        self.vars.borrow().list.clone()
    }

    /// The functions defined in this scope itself.
    pub fn own_functions(&self) -> Vec<(&'a str, Rc<FunctionDef<'a>>)> {
        self.functions.borrow().clone()
    }

    /// The modules defined in this scope itself.
    pub fn own_modules(&self) -> Vec<(&'a str, Rc<ModuleDef<'a>>)> {
        self.modules.borrow().clone()
    }

    /// The variable of this scope alone.
    pub fn get_local(&self, name: &str) -> Option<Value<'a>> {
        let vars = self.vars.borrow();
        vars.position(name).map(|i| vars.list[i].1.clone())
    }

    /// Looks a variable up: `$`-names along the dynamic chain, others along the lexical chain.
    pub fn lookup(self: &Rc<Self>, name: &str) -> Option<Value<'a>> {
        let special = name.starts_with('$');
        let mut frame = Some(self.clone());
        while let Some(f) = frame {
            if let Some(v) = f.get_local(name) {
                return Some(v);
            }
            frame = if special {
                f.dynamic.clone()
            } else {
                f.lexical.clone()
            };
        }
        None
    }

    /// Defines a function in this scope.
    pub fn define_function(&self, name: &'a str, def: Rc<FunctionDef<'a>>) {
        self.functions.borrow_mut().push((name, def));
    }

    /// Defines a module in this scope.
    pub fn define_module(&self, name: &'a str, def: Rc<ModuleDef<'a>>) {
        self.modules.borrow_mut().push((name, def));
    }

    /// Looks a user function up along the lexical chain (the last definition in a scope wins).
    pub fn lookup_function(self: &Rc<Self>, name: &str) -> Option<Rc<FunctionDef<'a>>> {
        self.lookup_definition(name, |frame| &frame.functions)
    }

    /// Looks a user module up along the lexical chain (the last definition in a scope wins).
    pub fn lookup_module(self: &Rc<Self>, name: &str) -> Option<Rc<ModuleDef<'a>>> {
        self.lookup_definition(name, |frame| &frame.modules)
    }

    /// The last definition of `name` in the table `table` picks out, searched frame by frame
    /// along the lexical chain.
    fn lookup_definition<T>(
        self: &Rc<Self>,
        name: &str,
        table: impl Fn(&Self) -> &RefCell<Vec<(&'a str, Rc<T>)>>,
    ) -> Option<Rc<T>> {
        let mut frame = Some(self.clone());
        while let Some(f) = frame {
            let found = table(&f)
                .borrow()
                .iter()
                .rev()
                .find(|(n, _)| *n == name)
                .map(|(_, d)| d.clone());
            if found.is_some() {
                return found;
            }
            frame = f.lexical.clone();
        }
        None
    }

    /// The children of the innermost module instance this scope is (lexically) inside.
    pub fn module_children(self: &Rc<Self>) -> Option<Rc<Children<'a>>> {
        let mut frame = Some(self.clone());
        while let Some(f) = frame {
            if let Some(c) = &f.children {
                return Some(c.clone());
            }
            frame = f.lexical.clone();
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ordinary_names_are_lexical_and_specials_dynamic() {
        let root = Frame::root();
        root.set("a", Value::Number(1.0));
        root.set("$s", Value::Number(1.0));
        let definition_site = Frame::nested(&root);
        let caller = Frame::nested(&root);
        caller.set("a", Value::Number(2.0));
        caller.set("$s", Value::Number(2.0));
        let callee = Frame::child(&definition_site, &caller);
        assert_eq!(callee.lookup("a").and_then(|v| v.as_number()), Some(1.0));
        assert_eq!(callee.lookup("$s").and_then(|v| v.as_number()), Some(2.0));
        assert!(callee.lookup("b").is_none());
    }

    #[test]
    fn large_scopes_keep_one_value_per_name_in_order() {
        let names: Vec<String> = (0..3 * INDEX_FROM).map(|i| format!("v{i}")).collect();
        let frame = Frame::root();
        for round in 0..2 {
            for (i, name) in names.iter().enumerate() {
                frame.set(name, Value::Number((i + round * 1000) as f64));
            }
        }
        let locals = frame.locals();
        assert_eq!(locals.len(), names.len());
        for (i, (name, value)) in locals.iter().enumerate() {
            assert_eq!(*name, names[i]);
            assert_eq!(value.as_number(), Some((i + 1000) as f64));
            assert_eq!(
                frame.get_local(name).and_then(|v| v.as_number()),
                Some((i + 1000) as f64)
            );
        }
        assert!(frame.get_local("v999").is_none());
    }
}
