//! How much code a specialization leaves for the driver to compile, measured on naga's IR.
//!
//! naga substitutes the override constants but writes every branch to SPIR-V, dead or not, so
//! the SPIR-V of every specialization is about the same size; the driver's compiler then
//! inlines every call and deletes the branches its constants decide. This does the same on
//! the IR: from the `render` entry point it walks each function once per call site (inlined,
//! with the call's constant arguments), follows only the taken side of a branch whose condition
//! is a constant (through locals, arguments and calls that return constants), and counts the
//! statements and expressions it reaches. What the driver compiles is roughly proportional to
//! that count; it is not the driver's own count.

use naga::{BinaryOperator, Block, Expression, Function, Handle, Literal, Statement};
use naga::{LocalVariable, Module, UnaryOperator};
use std::collections::{HashMap, HashSet};

/// Code reachable in a specialized kernel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KernelSize {
    /// IR statements and emitted expressions reachable from the entry point, every call
    /// inlined, branches on constants pruned.
    pub operations: usize,
    /// Distinct functions reached.
    pub functions: usize,
    /// SPIR-V words naga writes for the entry point (dead branches included).
    pub spirv_words: usize,
}

/// Measure `module` (overrides already applied) from entry point `entry`.
pub fn measure(module: &Module, entry: &str, spirv_words: usize) -> Option<KernelSize> {
    let ep = module.entry_points.iter().find(|e| e.name == entry)?;
    let mut walker = Walker {
        module,
        operations: 0,
        functions: HashSet::new(),
    };
    walker.function(&ep.function, Vec::new());
    Some(KernelSize {
        operations: walker.operations,
        functions: walker.functions.len() + 1,
        spirv_words,
    })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Value {
    Bool(bool),
    U32(u32),
    I32(i32),
}

struct Walker<'m> {
    module: &'m Module,
    operations: usize,
    functions: HashSet<Handle<Function>>,
}

/// One inlined call: its arguments, what its locals hold, the values of its expressions.
struct Call<'f> {
    function: &'f Function,
    args: Vec<Option<Value>>,
    locals: HashMap<Handle<LocalVariable>, Option<Value>>,
    values: HashMap<Handle<Expression>, Option<Value>>,
    returns: Vec<Option<Value>>,
}

impl<'m> Walker<'m> {
    /// Walk `function` called with `args`; its return value when every reachable `return`
    /// returns the same constant.
    fn function(&mut self, function: &'m Function, args: Vec<Option<Value>>) -> Option<Value> {
        let mut call = Call {
            function,
            args,
            locals: HashMap::new(),
            values: HashMap::new(),
            returns: Vec::new(),
        };
        for (handle, local) in function.local_variables.iter() {
            let init = local.init.and_then(|e| self.eval(&mut call, e));
            call.locals.insert(handle, init);
        }
        self.block(&mut call, &function.body);
        let first = *call.returns.first()?;
        call.returns.iter().all(|r| *r == first).then_some(first)?
    }

    /// Walk a block; true when it always leaves (return, break, continue, kill).
    fn block(&mut self, call: &mut Call<'m>, block: &'m Block) -> bool {
        for statement in block.iter() {
            if self.statement(call, statement) {
                return true;
            }
        }
        false
    }

    fn statement(&mut self, call: &mut Call<'m>, statement: &'m Statement) -> bool {
        match statement {
            Statement::Emit(range) => {
                for expr in range.clone() {
                    self.operations += 1;
                    let value = self.eval(call, expr);
                    call.values.insert(expr, value);
                }
                return false;
            }
            _ => self.operations += 1,
        }
        match statement {
            Statement::Block(block) => self.block(call, block),
            Statement::If {
                condition,
                accept,
                reject,
            } => match self.eval(call, *condition) {
                Some(Value::Bool(true)) => self.block(call, accept),
                Some(Value::Bool(false)) => self.block(call, reject),
                _ => {
                    let before = call.locals.clone();
                    let leaves_a = self.block(call, accept);
                    let after_a = std::mem::replace(&mut call.locals, before);
                    let leaves_r = self.block(call, reject);
                    // A local keeps a value only if both sides agree on it.
                    for (local, value) in call.locals.iter_mut() {
                        if after_a.get(local) != Some(value) {
                            *value = None;
                        }
                    }
                    leaves_a && leaves_r
                }
            },
            Statement::Switch { selector, cases } => {
                let selector = self.eval(call, *selector);
                let matches = |value: &naga::SwitchValue| match (value, selector) {
                    (naga::SwitchValue::I32(v), Some(Value::I32(s))) => Some(*v == s),
                    (naga::SwitchValue::U32(v), Some(Value::U32(s))) => Some(*v == s),
                    (naga::SwitchValue::Default, _) => None,
                    _ => None,
                };
                let known = selector.is_some();
                let chosen = cases
                    .iter()
                    .position(|c| matches(&c.value) == Some(true))
                    .or_else(|| {
                        cases
                            .iter()
                            .position(|c| c.value == naga::SwitchValue::Default)
                    });
                match (known, chosen) {
                    (true, Some(mut i)) => {
                        // The chosen case, and those it falls through to.
                        loop {
                            let leaves = self.block(call, &cases[i].body);
                            if leaves || !cases[i].fall_through || i + 1 == cases.len() {
                                return leaves;
                            }
                            i += 1;
                        }
                    }
                    _ => {
                        for case in cases {
                            self.block(call, &case.body);
                        }
                        call.locals.values_mut().for_each(|v| *v = None);
                        false
                    }
                }
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                // Any local may change from one iteration to the next.
                call.locals.values_mut().for_each(|v| *v = None);
                self.block(call, body);
                self.block(call, continuing);
                call.locals.values_mut().for_each(|v| *v = None);
                false
            }
            Statement::Break | Statement::Continue | Statement::Kill => true,
            Statement::Return { value } => {
                let value = value.and_then(|v| self.eval(call, v));
                call.returns.push(value);
                true
            }
            Statement::Store { pointer, value } => {
                if let Expression::LocalVariable(local) = call.function.expressions[*pointer] {
                    let value = self.eval(call, *value);
                    call.locals.insert(local, value);
                } else if let Some(local) = root_local(call.function, *pointer) {
                    // A store into part of a local (a member, an element).
                    call.locals.insert(local, None);
                }
                false
            }
            Statement::Call {
                function,
                arguments,
                result,
            } => {
                let args = arguments.iter().map(|a| self.eval(call, *a)).collect();
                self.functions.insert(*function);
                let callee = &self.module.functions[*function];
                let value = self.function(callee, args);
                if let Some(result) = result {
                    call.values.insert(*result, value);
                }
                // A local passed by pointer may have been written by the callee.
                for arg in arguments {
                    if let Some(local) = root_local(call.function, *arg) {
                        call.locals.insert(local, None);
                    }
                }
                false
            }
            _ => false,
        }
    }

    /// The constant value of `expr` in this call, if it has one.
    fn eval(&mut self, call: &mut Call<'m>, expr: Handle<Expression>) -> Option<Value> {
        if let Some(value) = call.values.get(&expr) {
            return *value;
        }
        let value = match &call.function.expressions[expr] {
            Expression::FunctionArgument(i) => call.args.get(*i as usize).copied().flatten(),
            Expression::Load { pointer } => match call.function.expressions[*pointer] {
                Expression::LocalVariable(local) => call.locals.get(&local).copied().flatten(),
                _ => None,
            },
            Expression::Unary { op, expr } => unary(*op, self.eval(call, *expr)?),
            Expression::Binary { op, left, right } => {
                let left = self.eval(call, *left);
                let right = self.eval(call, *right);
                binary(*op, left, right)
            }
            Expression::Select {
                condition,
                accept,
                reject,
            } => match self.eval(call, *condition)? {
                Value::Bool(true) => self.eval(call, *accept),
                Value::Bool(false) => self.eval(call, *reject),
                _ => None,
            },
            Expression::CallResult(_) => None,
            other => constant(self.module, other),
        };
        call.values.insert(expr, value);
        value
    }
}

/// The local variable a pointer expression points into, if any.
fn root_local(function: &Function, mut expr: Handle<Expression>) -> Option<Handle<LocalVariable>> {
    loop {
        match function.expressions[expr] {
            Expression::LocalVariable(local) => return Some(local),
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => expr = base,
            _ => return None,
        }
    }
}

/// The value of a literal, a module constant, or a scalar zero.
fn constant(module: &Module, expr: &Expression) -> Option<Value> {
    match expr {
        Expression::Literal(l) => literal(*l),
        Expression::Constant(c) => constant(
            module,
            &module.global_expressions[module.constants[*c].init],
        ),
        Expression::ZeroValue(ty) => match module.types[*ty].inner {
            naga::TypeInner::Scalar(s) => match s.kind {
                naga::ScalarKind::Bool => Some(Value::Bool(false)),
                naga::ScalarKind::Uint => Some(Value::U32(0)),
                naga::ScalarKind::Sint => Some(Value::I32(0)),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}

fn literal(l: Literal) -> Option<Value> {
    match l {
        Literal::Bool(b) => Some(Value::Bool(b)),
        Literal::U32(u) => Some(Value::U32(u)),
        Literal::I32(i) => Some(Value::I32(i)),
        _ => None,
    }
}

fn unary(op: UnaryOperator, v: Value) -> Option<Value> {
    match (op, v) {
        (UnaryOperator::LogicalNot, Value::Bool(b)) => Some(Value::Bool(!b)),
        (UnaryOperator::BitwiseNot, Value::U32(u)) => Some(Value::U32(!u)),
        (UnaryOperator::BitwiseNot, Value::I32(i)) => Some(Value::I32(!i)),
        (UnaryOperator::Negate, Value::I32(i)) => Some(Value::I32(i.wrapping_neg())),
        _ => None,
    }
}

fn binary(op: BinaryOperator, left: Option<Value>, right: Option<Value>) -> Option<Value> {
    use BinaryOperator as B;
    // `false && x`, `true || x`: decided by one side (naga keeps these for constant operands).
    match (op, left, right) {
        (B::LogicalAnd, Some(Value::Bool(false)), _)
        | (B::LogicalAnd, _, Some(Value::Bool(false))) => return Some(Value::Bool(false)),
        (B::LogicalOr, Some(Value::Bool(true)), _) | (B::LogicalOr, _, Some(Value::Bool(true))) => {
            return Some(Value::Bool(true))
        }
        _ => {}
    }
    let (left, right) = (left?, right?);
    let bool = |b| Some(Value::Bool(b));
    match (left, right) {
        (Value::Bool(a), Value::Bool(b)) => match op {
            B::Equal => bool(a == b),
            B::NotEqual => bool(a != b),
            B::LogicalAnd | B::And => bool(a && b),
            B::LogicalOr | B::InclusiveOr => bool(a || b),
            _ => None,
        },
        (Value::U32(a), Value::U32(b)) => compare(op, a, b).map(Value::Bool).or(match op {
            B::And => Some(Value::U32(a & b)),
            B::InclusiveOr => Some(Value::U32(a | b)),
            B::ExclusiveOr => Some(Value::U32(a ^ b)),
            B::Add => Some(Value::U32(a.wrapping_add(b))),
            B::Subtract => Some(Value::U32(a.wrapping_sub(b))),
            B::Multiply => Some(Value::U32(a.wrapping_mul(b))),
            B::ShiftLeft => Some(Value::U32(a.wrapping_shl(b))),
            B::ShiftRight => Some(Value::U32(a.wrapping_shr(b))),
            _ => None,
        }),
        (Value::I32(a), Value::I32(b)) => compare(op, a, b).map(Value::Bool).or(match op {
            B::Add => Some(Value::I32(a.wrapping_add(b))),
            B::Subtract => Some(Value::I32(a.wrapping_sub(b))),
            _ => None,
        }),
        // Shifts take a u32 amount whatever the operand.
        (Value::I32(a), Value::U32(b)) => match op {
            B::ShiftLeft => Some(Value::I32(a.wrapping_shl(b))),
            B::ShiftRight => Some(Value::I32(a.wrapping_shr(b))),
            _ => None,
        },
        _ => None,
    }
}

/// A comparison of two integers of one type, or `None` for another operator.
fn compare<T: PartialOrd>(op: BinaryOperator, a: T, b: T) -> Option<bool> {
    use BinaryOperator as B;
    Some(match op {
        B::Equal => a == b,
        B::NotEqual => a != b,
        B::Less => a < b,
        B::LessEqual => a <= b,
        B::Greater => a > b,
        B::GreaterEqual => a >= b,
        _ => return None,
    })
}
