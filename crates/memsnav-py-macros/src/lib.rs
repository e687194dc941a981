//! `#[catch_panics]`: every Python entry point of memsnav-py runs its body
//! through `crate::errors::catch_panics`, which turns a Rust panic into a
//! `memsnav.MemsnavError` instead of pyo3's `PanicException` (a
//! `BaseException` that `except Exception` does not catch).
//!
//! Put it above `#[pyfunction]` or above `#[pymethods]` (then every method
//! of the block is wrapped). A function returning a plain `T` is turned
//! into one returning `PyResult<T>`, the same to Python.
//!
//! The same attribute names the scalar arguments in their conversion
//! errors: each argument of a scalar type (`f64`, `usize`, `u64`, ... or an
//! `Option` of one) is read through `crate::convert::named_scalar` (pyo3's
//! own message, "must be real number, not str", does not say which
//! argument), by a small generated `from_py_with` function per argument.

use proc_macro::TokenStream;
use proc_macro2::TokenStream as Tokens;
use quote::format_ident;
use quote::quote;
use syn::{
    parse_macro_input, parse_quote, Block, FnArg, ImplItem, Item, Pat, ReturnType, Signature, Type,
};

/// Types read through `named_scalar`.
const SCALARS: [&str; 7] = ["f64", "f32", "usize", "u64", "u32", "i64", "i32"];

#[proc_macro_attribute]
pub fn catch_panics(args: TokenStream, item: TokenStream) -> TokenStream {
    if !args.is_empty() {
        return syn::Error::new(
            proc_macro2::Span::call_site(),
            "#[catch_panics] takes no arguments",
        )
        .to_compile_error()
        .into();
    }
    let mut item = parse_macro_input!(item as Item);
    let mut readers = Tokens::new();
    match &mut item {
        Item::Fn(f) => {
            readers.extend(name_scalars(&mut f.sig, ""));
            *f.block = wrapped(&mut f.sig.output, &f.block);
        }
        Item::Impl(block) => {
            let owner = match block.self_ty.as_ref() {
                Type::Path(p) => p.path.segments.last().map(|s| s.ident.to_string()),
                _ => None,
            }
            .unwrap_or_default();
            for member in &mut block.items {
                if let ImplItem::Fn(f) = member {
                    readers.extend(name_scalars(&mut f.sig, &owner));
                    f.block = wrapped(&mut f.sig.output, &f.block);
                }
            }
        }
        other => {
            return syn::Error::new_spanned(other, "#[catch_panics] goes on a fn or an impl block")
                .to_compile_error()
                .into()
        }
    }
    quote!(#readers #item).into()
}

/// Adds `#[pyo3(from_py_with = reader)]` to every scalar argument of `sig`
/// and returns the readers (free functions named after `owner`, the
/// function and the argument, so they are unique in the module).
fn name_scalars(sig: &mut Signature, owner: &str) -> Tokens {
    let mut readers = Tokens::new();
    for input in &mut sig.inputs {
        let FnArg::Typed(arg) = input else { continue };
        let Pat::Ident(name) = arg.pat.as_ref() else {
            continue;
        };
        if !is_scalar(&arg.ty) || arg.attrs.iter().any(|a| a.path().is_ident("pyo3")) {
            continue;
        }
        let argument = name.ident.to_string();
        let reader = format_ident!("__read_{}_{}_{}", owner, sig.ident, argument);
        let ty = &arg.ty;
        readers.extend(quote! {
            #[allow(non_snake_case)]
            fn #reader(obj: &::pyo3::Bound<'_, ::pyo3::PyAny>) -> ::pyo3::PyResult<#ty> {
                crate::convert::named_scalar(obj, #argument)
            }
        });
        arg.attrs
            .push(parse_quote!(#[pyo3(from_py_with = #reader)]));
    }
    readers
}

/// A scalar type of [`SCALARS`], or an `Option` of one.
fn is_scalar(ty: &Type) -> bool {
    let Type::Path(p) = ty else { return false };
    let Some(last) = p.path.segments.last() else {
        return false;
    };
    if SCALARS.iter().any(|s| last.ident == s) {
        return true;
    }
    if last.ident != "Option" {
        return false;
    }
    match &last.arguments {
        syn::PathArguments::AngleBracketed(a) => a.args.iter().any(|g| match g {
            syn::GenericArgument::Type(t) => is_scalar(t),
            _ => false,
        }),
        _ => false,
    }
}

fn returns_py_result(output: &ReturnType) -> bool {
    match output {
        ReturnType::Type(_, ty) => match ty.as_ref() {
            Type::Path(p) => p
                .path
                .segments
                .last()
                .is_some_and(|s| s.ident == "PyResult"),
            _ => false,
        },
        ReturnType::Default => false,
    }
}

/// The body run through `catch_panics`; a plain return type `T` becomes
/// `PyResult<T>` and the body's value `Ok(body)`.
fn wrapped(output: &mut ReturnType, body: &Block) -> Block {
    if returns_py_result(output) {
        return parse_quote!({ crate::errors::catch_panics(|| #body) });
    }
    let value: Type = match output {
        ReturnType::Default => parse_quote!(()),
        ReturnType::Type(_, ty) => (**ty).clone(),
    };
    *output = parse_quote!(-> ::pyo3::PyResult<#value>);
    parse_quote!({ crate::errors::catch_panics(|| ::std::result::Result::Ok(#body)) })
}
