//! `#[catch_panics]`: every Python entry point of memsnav-py runs its body
//! through `crate::errors::catch_panics`, which turns a Rust panic into a
//! `memsnav.MemsnavError` instead of pyo3's `PanicException` (a
//! `BaseException` that `except Exception` does not catch).
//!
//! Put it above `#[pyfunction]` or above `#[pymethods]` (then every method
//! of the block is wrapped). A function returning a plain `T` is turned
//! into one returning `PyResult<T>`, the same to Python.

use proc_macro::TokenStream;
use quote::quote;
use syn::{parse_macro_input, parse_quote, Block, ImplItem, Item, ReturnType, Type};

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
    match &mut item {
        Item::Fn(f) => *f.block = wrapped(&mut f.sig.output, &f.block),
        Item::Impl(block) => {
            for member in &mut block.items {
                if let ImplItem::Fn(f) = member {
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
    quote!(#item).into()
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
