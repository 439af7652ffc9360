//! Parse stage: the syntax tree of a `model!` block. Touches only tokens; knows nothing about
//! which constructors or keys exist (that is `check.rs`).
//!
//! Grammar (each node below documents the part it accepts):
//!
//! ```text
//! model      := attr* vis ["assembly"] Name ["(" param,* ")"] "{" component,* "}"
//! param      := attr* name ":" Type "=" default-expr
//! component  := attr* name "=" ctor
//! ctor       := Path ["(" (key "=" value),* ")"]
//! value      := ctor | expr          (decided per key by the check stage)
//! ```

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::spanned::Spanned;
use syn::{braced, parenthesized, Attribute, Expr, Ident, Token, Type, Visibility};

/// A whole `model!` block: one model or assembly type.
pub(crate) struct ModelDef {
    /// Outer attributes, doc comments among them; copied onto the generated struct.
    pub attrs: Vec<Attribute>,
    /// Visibility of the generated type.
    pub vis: Visibility,
    /// The `assembly` keyword if present: a sub-assembly (no `Scene`, no `build()`).
    pub assembly: Option<Ident>,
    /// The generated type's name.
    pub name: Ident,
    /// Parameters: public fields of the generated type, locals in every value.
    pub params: Vec<Param>,
    /// Components in declaration order.
    pub components: Vec<Component>,
}

/// `name: Type = default` — a parameter.
pub(crate) struct Param {
    /// Doc comments and other attributes, copied onto the field.
    pub attrs: Vec<Attribute>,
    /// Field name.
    pub name: Ident,
    /// Field type.
    pub ty: Type,
    /// Default value.
    pub default: Expr,
}

/// `name = Constructor(key = value, …)` — one component of the model.
pub(crate) struct Component {
    /// The component's name (object, joint, force element, material or sub-assembly).
    pub name: Ident,
    /// Its constructor.
    pub ctor: Ctor,
}

/// `Path(key = value, …)`, or a bare `Path` with no arguments.
pub(crate) struct Ctor {
    /// The constructor as written (a single identifier for built-ins).
    pub path: syn::Path,
    /// The arguments in source order.
    pub args: Vec<Arg>,
}

impl Ctor {
    /// The last path segment (`Revolute`, `Arm`).
    pub(crate) fn name(&self) -> &Ident {
        &self.path.segments.last().expect("non-empty path").ident
    }
    /// Whether the constructor is a single identifier (built-ins are).
    pub(crate) fn is_single(&self) -> bool {
        self.path.leading_colon.is_none() && self.path.segments.len() == 1
    }
}

/// `key = value`.
pub(crate) struct Arg {
    /// The key.
    pub key: Ident,
    /// The value, as a Rust expression (nested constructors are expressions too).
    pub value: Expr,
}

impl Parse for ModelDef {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        let mut assembly = None;
        if input.peek(Ident) && input.peek2(Ident) {
            let kw: Ident = input.parse()?;
            if kw != "assembly" {
                return Err(syn::Error::new(
                    kw.span(),
                    format!("expected `assembly` or a model name, found `{kw}`"),
                ));
            }
            assembly = Some(kw);
        }
        let name: Ident = input.parse().map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected a model name (hint: `pub Pendulum(length: f64 = 1.0) { … }`)",
            )
        })?;
        let mut params = vec![];
        if input.peek(syn::token::Paren) {
            let content;
            parenthesized!(content in input);
            params = Punctuated::<Param, Token![,]>::parse_terminated(&content)?
                .into_iter()
                .collect();
        }
        if !input.peek(syn::token::Brace) {
            return Err(input.error("expected `{` and the components of the model"));
        }
        let content;
        braced!(content in input);
        let components = Punctuated::<Component, Token![,]>::parse_terminated(&content)?
            .into_iter()
            .collect();
        if !input.is_empty() {
            return Err(
                input.error("unexpected tokens after the model: one `model!` defines one type")
            );
        }
        Ok(ModelDef {
            attrs,
            vis,
            assembly,
            name,
            params,
            components,
        })
    }
}

impl Parse for Param {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let name: Ident = input.parse()?;
        if !input.peek(Token![:]) {
            return Err(syn::Error::new(
                name.span(),
                format!(
                    "parameter `{name}` needs a type and a default (hint: `{name}: f64 = 1.0`)"
                ),
            ));
        }
        input.parse::<Token![:]>()?;
        let ty: Type = input.parse()?;
        if !input.peek(Token![=]) {
            return Err(syn::Error::new(
                name.span(),
                format!("parameter `{name}` needs a default value (hint: `{name}: … = 1.0`)"),
            ));
        }
        input.parse::<Token![=]>()?;
        let default: Expr = input.parse()?;
        Ok(Param {
            attrs,
            name,
            ty,
            default,
        })
    }
}

impl Parse for Component {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        // Doc comments on components are accepted and dropped.
        let _ = input.call(Attribute::parse_outer)?;
        let name: Ident = input.parse()?;
        if !input.peek(Token![=]) {
            return Err(syn::Error::new(
                name.span(),
                format!("expected `=` after component `{name}` (hint: `{name} = Object3D(…)`)"),
            ));
        }
        input.parse::<Token![=]>()?;
        let value: Expr = input.parse()?;
        let ctor = Ctor::from_expr(&value)?.ok_or_else(|| {
            syn::Error::new(
                value.span(),
                format!("expected a constructor for `{name}`, like `Object3D(…)` or `Revolute(…)`"),
            )
        })?;
        Ok(Component { name, ctor })
    }
}

impl Ctor {
    /// Reads `Path(key = value, …)` or a bare `Path` out of an expression. `Ok(None)` when the
    /// expression is not a call or path at all; an error when it is a call whose arguments are
    /// not `key = value`.
    pub(crate) fn from_expr(e: &Expr) -> syn::Result<Option<Ctor>> {
        match e {
            Expr::Path(p) if p.qself.is_none() && p.attrs.is_empty() => Ok(Some(Ctor {
                path: p.path.clone(),
                args: vec![],
            })),
            Expr::Call(c) => {
                let Expr::Path(p) = &*c.func else {
                    return Ok(None);
                };
                if p.qself.is_some() {
                    return Ok(None);
                }
                let mut args = vec![];
                let mut err: Option<syn::Error> = None;
                for a in &c.args {
                    match a {
                        Expr::Assign(asg) => match &*asg.left {
                            Expr::Path(k) if k.path.get_ident().is_some() => args.push(Arg {
                                key: k.path.get_ident().cloned().expect("checked"),
                                value: (*asg.right).clone(),
                            }),
                            other => push(
                                &mut err,
                                syn::Error::new(other.span(), "expected a key name before `=`"),
                            ),
                        },
                        other => push(
                            &mut err,
                            syn::Error::new(
                                other.span(),
                                format!(
                                    "expected `key = value` in `{}(…)`",
                                    quote::ToTokens::to_token_stream(&p.path)
                                        .to_string()
                                        .replace(' ', "")
                                ),
                            ),
                        ),
                    }
                }
                match err {
                    Some(e) => Err(e),
                    None => Ok(Some(Ctor {
                        path: p.path.clone(),
                        args,
                    })),
                }
            }
            _ => Ok(None),
        }
    }

    /// The span of the constructor's name.
    pub(crate) fn span(&self) -> Span {
        self.name().span()
    }
}

/// Adds `e` to an optional combined error.
pub(crate) fn push(acc: &mut Option<syn::Error>, e: syn::Error) {
    match acc {
        Some(a) => a.combine(e),
        None => *acc = Some(e),
    }
}
