//! `#[guard]`, the one panic boundary of `gnssatt._core`: put above a `#[pyfunction]` or a `#[pymethods]`
//! impl, it runs the body of the function (of every method) inside `crate::guard::call`, which turns a
//! panic into `gnssatt.errors.InternalError` (an ordinary `Exception`) instead of pyo3's
//! `PanicException` (a `BaseException`, which `except Exception` misses). A function or method that
//! returns a plain value is made to return `PyResult` of it, so that it too can raise.
//!
//! An attribute and not a wrapper written into each body: one line per entry point, and
//! `tests/test_panic_guard.py` checks that no `#[pyfunction]` or `#[pymethods]` lacks it.

use proc_macro::TokenStream;
use quote::quote;
use syn::{parse_macro_input, parse_quote, Block, ImplItem, Item, ReturnType, Signature, Type};

#[proc_macro_attribute]
pub fn guard(attr: TokenStream, item: TokenStream) -> TokenStream {
    if !attr.is_empty() {
        return quote!(compile_error!("#[guard] takes no arguments");).into();
    }
    match parse_macro_input!(item as Item) {
        Item::Fn(mut f) => {
            wrap(&mut f.sig, &mut f.block);
            quote!(#f).into()
        }
        Item::Impl(mut block) => {
            for item in &mut block.items {
                if let ImplItem::Fn(method) = item {
                    wrap(&mut method.sig, &mut method.block);
                }
            }
            quote!(#block).into()
        }
        other => syn::Error::new_spanned(
            other,
            "#[guard] goes on a #[pyfunction] or a #[pymethods] impl",
        )
        .to_compile_error()
        .into(),
    }
}

/// `PyResult<...>` (or a path ending in it): the body already returns the error type.
fn is_py_result(ty: &Type) -> bool {
    match ty {
        Type::Path(p) => p
            .path
            .segments
            .last()
            .is_some_and(|s| s.ident == "PyResult"),
        _ => false,
    }
}

fn wrap(sig: &mut Signature, block: &mut Block) {
    let name = sig.ident.to_string();
    let body = &*block;
    let work = match &sig.output {
        ReturnType::Type(_, ty) if is_py_result(ty) => quote!(#body),
        ReturnType::Type(_, ty) => {
            let ty = ty.clone();
            sig.output = parse_quote!(-> ::pyo3::PyResult<#ty>);
            quote!(::std::result::Result::Ok(#body))
        }
        ReturnType::Default => {
            sig.output = parse_quote!(-> ::pyo3::PyResult<()>);
            quote!(::std::result::Result::Ok(#body))
        }
    };
    *block = parse_quote!({ crate::guard::call(#name, move || #work) });
}
