//! Normalisation after parsing, before the checks: integer literals where the core expects a
//! float become float literals with the same span (`[0, 0, -1]` → `[0.0, 0.0, -1.0]`,
//! `diameter = 1`, `inertia = [[1, 0, 0], …]`, `Var(init = [0, 0, 1])`, a parameter
//! `h: f64 = 2`), so rustc does not report one E0308 per element. Only plain literals are
//! touched (also negated or parenthesised, and inside array literals and nested
//! built-in constructors); suffixed literals (`2u32`), integer-valued keys (`axis = 3`,
//! `mpr_max_iterations = 50`) and every other expression stay as written, so their errors are
//! unchanged.

use crate::ast::ModelDef;
use crate::vocab::{is_block_value, is_component, is_nested, joint_kind};
use syn::{Expr, Lit, LitFloat};

/// Keys whose scalar value is an integer (an array value of such a key is still a float
/// vector: `axis = [0, 1, 0]`); the axis keys of the other joint kinds (`axis1`, `normal`, …)
/// come from the core's table ([`joint_kind`]), so a new joint kind needs no entry here.
const INTEGER_KEYS: &[&str] = &["axis", "mpr_max_iterations"];

/// Whether `key` of constructor `ctor` takes an integer scalar (a Modia axis index or a count).
fn integer_key(ctor: &str, key: &str) -> bool {
    INTEGER_KEYS.contains(&key)
        || joint_kind(ctor).is_some_and(|k| k.axes.iter().any(|a| a.key == key))
}

/// Rewrites the integer literals of `def` that stand for floats (see the module header).
pub(crate) fn floatify(def: &mut ModelDef) {
    for p in &mut def.params {
        if matches!(&p.ty, syn::Type::Path(t) if t.path.is_ident("f64")) {
            value(&mut p.default, false);
        }
    }
    // Built-in constructors only: a sub-assembly's parameters may be integers.
    for c in &mut def.components {
        let name = c.ctor.name().to_string();
        if !(c.ctor.is_single() && is_component(&name)) {
            continue;
        }
        for a in &mut c.ctor.args {
            let key = a.key.to_string();
            value(&mut a.value, integer_key(&name, &key));
        }
    }
}

/// One value; `integer_scalar`: a top-level integer literal stays.
fn value(e: &mut Expr, integer_scalar: bool) {
    match e {
        Expr::Lit(l) => {
            if let Lit::Int(i) = &l.lit {
                if !integer_scalar && i.suffix().is_empty() {
                    let f = LitFloat::new(&format!("{}.0", i.base10_digits()), i.span());
                    l.lit = Lit::Float(f);
                }
            }
        }
        Expr::Unary(u) if matches!(u.op, syn::UnOp::Neg(_)) => value(&mut u.expr, integer_scalar),
        Expr::Paren(p) => value(&mut p.expr, integer_scalar),
        Expr::Group(g) => value(&mut g.expr, integer_scalar),
        Expr::Array(arr) => arr.elems.iter_mut().for_each(|el| value(el, false)),
        // A `Table`'s `(time, value)` rows.
        Expr::Tuple(t) => t.elems.iter_mut().for_each(|el| value(el, false)),
        // A built-in nested constructor `Ctor(key = value, …)`, a block's variant
        // (`Elastic(c = …, d = …)`) or inner block (`inner = PI(…)`).
        Expr::Call(call)
            if matches!(&*call.func, Expr::Path(p)
            if p.path.get_ident().is_some_and(|i| {
                let n = i.to_string();
                is_nested(&n) || is_block_value(&n)
            })) =>
        {
            for arg in call.args.iter_mut() {
                if let Expr::Assign(asg) = arg {
                    let key = match &*asg.left {
                        Expr::Path(p) => p.path.get_ident().map(|i| i.to_string()),
                        _ => None,
                    };
                    let int = key.is_some_and(|k| INTEGER_KEYS.contains(&k.as_str()));
                    value(&mut asg.right, int);
                }
            }
        }
        _ => {}
    }
}
