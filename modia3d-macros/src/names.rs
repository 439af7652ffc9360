//! Names: references to components (`body`, `arm1.tip`), the hidden paths module of a
//! generated type (what rustc checks references into sub-assemblies against), and the attach
//! rule that decides which parts of an assembly hang from the `parent` handed to `add_to`.
//! Plain data on syntax; no code generation.

pub(crate) use crate::ir::NameRef;
use crate::ir::{Item, JointIr, ObjectIr, Parent};
use proc_macro2::Ident;
use std::collections::{HashMap, HashSet};
use syn::Expr;

pub(crate) use modia3d_core::scene::did_you_mean;

/// ` (hint: did you mean `x`?)` or nothing.
pub(crate) fn hint(h: Option<String>) -> String {
    h.map(|h| format!(" (hint: did you mean `{h}`?)"))
        .unwrap_or_default()
}

/// `a` or `a.b.c` → identifiers; false for anything else.
pub(crate) fn path_segments(e: &Expr, out: &mut Vec<Ident>) -> bool {
    match e {
        Expr::Path(p) if p.qself.is_none() => match p.path.get_ident() {
            Some(id) => {
                out.push(id.clone());
                true
            }
            None => false,
        },
        Expr::Field(f) => {
            if !path_segments(&f.base, out) {
                return false;
            }
            match &f.member {
                syn::Member::Named(id) => {
                    out.push(id.clone());
                    true
                }
                syn::Member::Unnamed(_) => false,
            }
        }
        _ => false,
    }
}

/// The hidden paths module of a generated type, given the type's path as written:
/// `a::Arm` → `a::__modia3d_Arm`. With `from_module`, relative paths are made to work from
/// inside another hidden module (one level deeper).
pub(crate) fn paths_module(ty: &syn::Path, from_module: bool) -> syn::Path {
    let mut p = ty.clone();
    let last = p.segments.last_mut().expect("non-empty path");
    last.ident = Ident::new(&format!("__modia3d_{}", last.ident), last.ident.span());
    last.arguments = syn::PathArguments::None;
    if from_module && p.leading_colon.is_none() {
        let first = p.segments[0].ident.to_string();
        if first == "self" {
            p.segments[0].ident = Ident::new("super", p.segments[0].ident.span());
        } else if first != "crate" {
            let span = p.segments[0].ident.span();
            p.segments.insert(0, Ident::new("super", span).into());
        }
    }
    p
}

/// The attach rule: an assembly's root-level parts — objects without `parent` whose rigid
/// group (parent links) no joint of the block moves, and sub-assemblies without `parent`
/// that no joint of the block moves — take the `parent` handed to `add_to`.
pub(crate) fn attach_roots(items: &mut [Item]) {
    let parent_of: HashMap<String, String> = items
        .iter()
        .filter_map(|it| match it {
            Item::Object(ObjectIr {
                name,
                parent: Parent::Ref(r),
                ..
            }) => Some((name.to_string(), r.path.clone())),
            _ => None,
        })
        .collect();
    // The root of an object's parent chain (parent cycles are errors, reported before).
    let root = |start: &str| {
        let mut cur = start.to_string();
        let mut steps = 0;
        while let Some(p) = parent_of.get(&cur) {
            cur = p.clone();
            steps += 1;
            if steps > parent_of.len() {
                break;
            }
        }
        cur
    };
    let moved: Vec<&str> = items
        .iter()
        .filter_map(|it| match it {
            Item::Joint(JointIr { obj2, .. }) => Some(obj2.path.as_str()),
            _ => None,
        })
        .collect();
    let moved_roots: HashSet<String> = moved
        .iter()
        .filter(|p| !p.contains('.'))
        .map(|p| root(p))
        .collect();
    let moved: Vec<String> = moved.iter().map(|s| s.to_string()).collect();
    for it in items.iter_mut() {
        match it {
            Item::Object(ObjectIr {
                name,
                parent,
                scene,
                ..
            }) if matches!(parent, Parent::None)
                && !*scene
                && !moved_roots.contains(&name.to_string()) =>
            {
                *parent = Parent::Attach;
            }
            Item::Assembly { name, parent, .. } => {
                let inside = format!("{name}.");
                if matches!(parent, Parent::Attach) && moved.iter().any(|p| p.starts_with(&inside))
                {
                    *parent = Parent::None;
                }
            }
            _ => {}
        }
    }
}
