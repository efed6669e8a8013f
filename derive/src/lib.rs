//! `#[derive(SceneKeys)]`: a section of demsweep's scene configuration, written as a plain struct,
//! gets `KEYS`, its fields' `KeyDoc`s (`demsweep::physics::key_spec`). Each field's doc comment is
//! its description and its `#[key(...)]` line the fields of a `KeySpec` (`unit: "m", range: "> 0",
//! plausible: Some((..)), one_of: &[..], table: Some(Section::KEYS)`; the rest default to none).
//! A derive reads the struct as declared; a `macro_rules!` macro could only by wrapping it.

use proc_macro::TokenStream;
use proc_macro2::TokenStream as Tokens;
use quote::quote;
use syn::{Data, DeriveInput, Error, Fields, Meta, parse_macro_input};

/// Generates `KEYS` for a struct with named fields, each with its doc comment and `#[key(...)]`.
#[proc_macro_derive(SceneKeys, attributes(key))]
pub fn derive_scene_keys(input: TokenStream) -> TokenStream {
    let input = parse_macro_input!(input as DeriveInput);
    keys_impl(&input).unwrap_or_else(Error::into_compile_error).into()
}

fn keys_impl(input: &DeriveInput) -> syn::Result<Tokens> {
    let fields = match &input.data {
        Data::Struct(data) => match &data.fields {
            Fields::Named(named) => named.named.iter().collect(),
            Fields::Unit => Vec::new(),
            Fields::Unnamed(_) => return Err(Error::new_spanned(&input.ident, "SceneKeys needs named fields")),
        },
        _ => return Err(Error::new_spanned(&input.ident, "SceneKeys derives only for a struct")),
    };
    let docs = fields.iter().map(|field| key_doc(field)).collect::<syn::Result<Vec<Tokens>>>()?;
    let name = &input.ident;
    let (generics, arguments, bounds) = input.generics.split_for_impl();
    Ok(quote! {
        impl #generics #name #arguments #bounds {
            /// The section's keys (`physics::keys`).
            pub const KEYS: &'static [crate::physics::key_spec::KeyDoc] = &[#(#docs),*];
        }
    })
}

/// A field's `KeyDoc`: its name, its doc comment's lines and its `#[key(...)]` as a `KeySpec`.
fn key_doc(field: &syn::Field) -> syn::Result<Tokens> {
    let ident = field.ident.as_ref().ok_or_else(|| Error::new_spanned(field, "SceneKeys needs named fields"))?;
    let mut lines = Vec::new();
    let mut spec = None;
    for attr in &field.attrs {
        match &attr.meta {
            Meta::NameValue(doc) if doc.path.is_ident("doc") => lines.push(&doc.value),
            Meta::List(key) if key.path.is_ident("key") => spec = Some(&key.tokens),
            _ if attr.path().is_ident("key") => return Err(Error::new_spanned(attr, "write #[key(name: value, ..)]")),
            _ => {}
        }
    }
    let spec = spec.ok_or_else(|| Error::new_spanned(ident, "every key declares its #[key(...)] (empty: none)"))?;
    let spec = if spec.is_empty() {
        quote! { crate::physics::key_spec::KeySpec::NONE }
    } else {
        quote! { crate::physics::key_spec::KeySpec { #spec, ..crate::physics::key_spec::KeySpec::NONE } }
    };
    Ok(quote! {
        crate::physics::key_spec::KeyDoc { name: stringify!(#ident), doc: &[#(#lines),*], spec: #spec }
    })
}
