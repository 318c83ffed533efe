//! `#[derive(Compact)]` for the `compact` codec: on a struct (named, tuple or unit) whose
//! fields are bounded numbers, booleans, options of them, or other `Compact` types; and on a
//! fieldless enum. Field bounds come from `#[compact(min = A, max = B, resolution = R)]`
//! (`resolution` for floats only) with an optional `clamp` (the default) or `reject`. The
//! macro checks the bounds at compile time and computes every field's code range, so the
//! message's size is a constant. The generated code names the runtime as `::compact`; see
//! that crate's documentation for the encoding.

use proc_macro2::{Literal, Span, TokenStream};
use quote::{format_ident, quote};
use syn::{Data, DeriveInput, Fields, GenericArgument, PathArguments, Type, parse_macro_input};

/// Derives `compact::Compact` (see the `compact` crate).
#[proc_macro_derive(Compact, attributes(compact))]
pub fn derive_compact(input: proc_macro::TokenStream) -> proc_macro::TokenStream {
    let input = parse_macro_input!(input as DeriveInput);
    match expand(&input) {
        Ok(ts) => ts.into(),
        Err(e) => e.to_compile_error().into(),
    }
}

fn expand(input: &DeriveInput) -> syn::Result<TokenStream> {
    if !input.generics.params.is_empty() {
        return Err(syn::Error::new_spanned(
            &input.generics,
            "Compact does not support generic types",
        ));
    }
    match &input.data {
        Data::Struct(s) => expand_struct(input, &s.fields),
        Data::Enum(e) => expand_enum(input, e),
        Data::Union(_) => Err(syn::Error::new_spanned(
            &input.ident,
            "Compact cannot be derived for a union",
        )),
    }
}

fn expand_enum(input: &DeriveInput, e: &syn::DataEnum) -> syn::Result<TokenStream> {
    let name = &input.ident;
    if e.variants.is_empty() {
        return Err(syn::Error::new_spanned(
            name,
            "Compact needs at least one variant",
        ));
    }
    let mut write_arms = Vec::new();
    let mut read_arms = Vec::new();
    for (k, v) in e.variants.iter().enumerate() {
        if !matches!(v.fields, Fields::Unit) {
            return Err(syn::Error::new_spanned(
                v,
                "Compact enums must be fieldless",
            ));
        }
        let ident = &v.ident;
        let k = k as u64;
        write_arms.push(quote! { Self::#ident => #k });
        read_arms.push(quote! { #k => ::core::result::Result::Ok(Self::#ident) });
    }
    let steps = e.variants.len() as u64 - 1;
    let type_name = name.to_string();
    Ok(quote! {
        impl ::compact::Compact for #name {
            const SIZE_BITS: usize = ::compact::bits_for(#steps) as usize;
            fn write_bits(&self, w: &mut ::compact::BitWriter<'_>)
                -> ::core::result::Result<(), ::compact::EncodeError> {
                let k: u64 = match self { #(#write_arms,)* };
                w.write(k, ::compact::bits_for(#steps))
            }
            fn read_bits(r: &mut ::compact::BitReader<'_>)
                -> ::core::result::Result<Self, ::compact::DecodeError> {
                match r.read(::compact::bits_for(#steps))? {
                    #(#read_arms,)*
                    _ => ::core::result::Result::Err(
                        ::compact::DecodeError::BadValue { field: #type_name }),
                }
            }
        }
    })
}

/// A number literal from an attribute, with its sign.
#[derive(Clone, Copy)]
enum Num {
    Int(i128),
    Float(f64),
}

impl Num {
    fn as_f64(self) -> f64 {
        match self {
            Num::Int(i) => i as f64,
            Num::Float(f) => f,
        }
    }
}

#[derive(Default)]
struct Attrs {
    min: Option<Num>,
    max: Option<Num>,
    resolution: Option<Num>,
    reject: bool,
    span: Option<Span>,
}

fn parse_num(input: syn::parse::ParseStream<'_>) -> syn::Result<Num> {
    let neg = input.peek(syn::Token![-]);
    if neg {
        input.parse::<syn::Token![-]>()?;
    }
    let lit: syn::Lit = input.parse()?;
    let n = match &lit {
        syn::Lit::Int(i) => Num::Int(i.base10_parse::<i128>()?),
        syn::Lit::Float(f) => Num::Float(f.base10_parse::<f64>()?),
        _ => return Err(syn::Error::new_spanned(lit, "expected a number")),
    };
    Ok(match (n, neg) {
        (Num::Int(i), true) => Num::Int(-i),
        (Num::Float(f), true) => Num::Float(-f),
        (n, false) => n,
    })
}

fn field_attrs(attrs: &[syn::Attribute]) -> syn::Result<Attrs> {
    let mut a = Attrs::default();
    for attr in attrs.iter().filter(|at| at.path().is_ident("compact")) {
        a.span = Some(attr.pound_token.span);
        attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("min") {
                a.min = Some(parse_num(meta.value()?)?);
            } else if meta.path.is_ident("max") {
                a.max = Some(parse_num(meta.value()?)?);
            } else if meta.path.is_ident("resolution") {
                a.resolution = Some(parse_num(meta.value()?)?);
            } else if meta.path.is_ident("reject") {
                a.reject = true;
            } else if meta.path.is_ident("clamp") {
                a.reject = false;
            } else {
                return Err(meta.error("expected min, max, resolution, clamp or reject"));
            }
            Ok(())
        })?;
    }
    Ok(a)
}

fn type_ident(ty: &Type) -> Option<String> {
    match ty {
        Type::Path(p) if p.qself.is_none() => p.path.segments.last().map(|s| s.ident.to_string()),
        _ => None,
    }
}

fn option_inner(ty: &Type) -> Option<&Type> {
    let Type::Path(p) = ty else { return None };
    let seg = p.path.segments.last()?;
    if seg.ident != "Option" {
        return None;
    }
    let PathArguments::AngleBracketed(args) = &seg.arguments else {
        return None;
    };
    match args.args.first() {
        Some(GenericArgument::Type(t)) if args.args.len() == 1 => Some(t),
        _ => None,
    }
}

fn int_bounds(name: &str) -> Option<(i128, i128)> {
    Some(match name {
        "u8" => (0, u8::MAX.into()),
        "u16" => (0, u16::MAX.into()),
        "u32" => (0, u32::MAX.into()),
        "u64" => (0, u64::MAX.into()),
        "i8" => (i8::MIN.into(), i8::MAX.into()),
        "i16" => (i16::MIN.into(), i16::MAX.into()),
        "i32" => (i32::MIN.into(), i32::MAX.into()),
        "i64" => (i64::MIN.into(), i64::MAX.into()),
        _ => return None,
    })
}

fn float_lit(v: f64) -> TokenStream {
    let lit = Literal::f64_suffixed(v.abs());
    if v.is_sign_negative() && v != 0.0 {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

fn int_lit(v: i128) -> TokenStream {
    let lit = Literal::i128_suffixed(v.unsigned_abs() as i128);
    if v < 0 { quote!(-#lit) } else { quote!(#lit) }
}

/// What one field generates: its size in bits (an expression), its write statement and its
/// read expression (reading into a `Result`).
struct FieldCode {
    bits: TokenStream,
    write: TokenStream,
    read: TokenStream,
}

fn field_code(
    label: &str,
    access: &TokenStream,
    ty: &Type,
    attrs: &Attrs,
) -> syn::Result<FieldCode> {
    let (inner, optional) = match option_inner(ty) {
        Some(t) => (t, true),
        None => (ty, false),
    };
    let tname = type_ident(inner).unwrap_or_default();
    let policy = if attrs.reject {
        quote!(::compact::OutOfRange::Reject)
    } else {
        quote!(::compact::OutOfRange::Clamp)
    };
    let has_bounds = attrs.min.is_some() || attrs.max.is_some() || attrs.resolution.is_some();
    let err = |msg: &str| syn::Error::new(attrs.span.unwrap_or_else(Span::call_site), msg);
    let opt = u64::from(optional);

    // The code of the value `v` (an expression), the value of the code `k`, and the highest
    // code: shared by numbers and booleans, optional or not.
    let (code_of, value_of, steps): (TokenStream, TokenStream, u64) = match tname.as_str() {
        "f32" | "f64" => {
            let (Some(min), Some(max), Some(res)) = (attrs.min, attrs.max, attrs.resolution) else {
                return Err(err(&format!(
                    "{label}: a float field needs #[compact(min = .., max = .., resolution = ..)]"
                )));
            };
            let (min, max, res) = (min.as_f64(), max.as_f64(), res.as_f64());
            if !(min.is_finite() && max.is_finite() && res.is_finite() && max > min && res > 0.0) {
                return Err(err(&format!(
                    "{label}: needs finite bounds with min < max and resolution > 0"
                )));
            }
            let ratio = (max - min) / res;
            let steps_f = ratio.round();
            if (ratio - steps_f).abs() > 1e-6 * ratio.max(1.0) || steps_f > (1u64 << 53) as f64 {
                return Err(err(&format!(
                    "{label}: max - min must be a whole number of resolutions (at most 2^53)"
                )));
            }
            let steps = steps_f as u64;
            let (minl, maxl, resl) = (float_lit(min), float_lit(max), float_lit(res));
            let codec = quote! {
                ::compact::Fixed { name: #label, min: #minl, max: #maxl, resolution: #resl,
                    steps: #steps, policy: #policy }
            };
            let (to_f64, from_f64) = if tname == "f32" {
                (quote!(f64::from(v)), quote!((x as f32)))
            } else {
                (quote!(v), quote!(x))
            };
            (
                quote!({ const C: ::compact::Fixed = #codec; C.code(#to_f64)? }),
                quote!({ const C: ::compact::Fixed = #codec; let x = C.value(k)?; #from_f64 }),
                steps,
            )
        }
        t if int_bounds(t).is_some() => {
            let (tmin, tmax) = int_bounds(t).unwrap_or_default();
            if attrs.resolution.is_some() {
                return Err(err(&format!(
                    "{label}: an integer field takes no resolution"
                )));
            }
            let get = |n: Option<Num>, d: i128| match n {
                None => Ok(d),
                Some(Num::Int(i)) => Ok(i),
                Some(Num::Float(_)) => {
                    Err(err(&format!("{label}: integer bounds must be integers")))
                }
            };
            let (min, max) = (get(attrs.min, tmin)?, get(attrs.max, tmax)?);
            if min >= max || min < tmin || max > tmax {
                return Err(err(&format!(
                    "{label}: needs min < max within the type's own range"
                )));
            }
            let steps = (max - min) as u64;
            let (minl, maxl) = (int_lit(min), int_lit(max));
            let ity = format_ident!("{}", t);
            let codec = quote! {
                ::compact::Int { name: #label, min: #minl, max: #maxl, policy: #policy }
            };
            (
                quote!({ const C: ::compact::Int = #codec; C.code(v as i128)? }),
                quote!({
                    const C: ::compact::Int = #codec;
                    <#ity as ::core::convert::TryFrom<i128>>::try_from(C.value(k)?)
                        .map_err(|_| ::compact::DecodeError::BadValue { field: #label })?
                }),
                steps,
            )
        }
        "bool" => {
            if has_bounds {
                return Err(err(&format!("{label}: a bool field takes no bounds")));
            }
            (
                quote!(u64::from(v)),
                quote!({
                    if k > 1 {
                        return ::core::result::Result::Err(
                            ::compact::DecodeError::BadValue { field: #label });
                    }
                    k == 1
                }),
                1,
            )
        }
        _ => {
            // A nested Compact type.
            if has_bounds {
                return Err(err(&format!(
                    "{label}: bounds apply to numbers only; a nested type carries its own"
                )));
            }
            let bits = quote!(<#inner as ::compact::Compact>::SIZE_BITS);
            return Ok(if optional {
                FieldCode {
                    bits: quote!((1 + #bits)),
                    write: quote! {
                        match &#access {
                            ::core::option::Option::Some(v) => {
                                w.write(1, 1)?;
                                ::compact::Compact::write_bits(v, w)?;
                            }
                            ::core::option::Option::None => {
                                w.write(0, 1)?;
                                w.write_zeros(#bits)?;
                            }
                        }
                    },
                    read: quote! {
                        if r.read(1)? == 1 {
                            ::core::option::Option::Some(
                                <#inner as ::compact::Compact>::read_bits(r)?)
                        } else {
                            r.expect_zeros(#bits, #label)?;
                            ::core::option::Option::None
                        }
                    },
                }
            } else {
                FieldCode {
                    bits,
                    write: quote!(::compact::Compact::write_bits(&#access, w)?;),
                    read: quote!(<#inner as ::compact::Compact>::read_bits(r)?),
                }
            });
        }
    };

    let nbits = quote!(::compact::bits_for(#steps + #opt));
    let (write, read) = if optional {
        (
            quote! {
                let code: u64 = match #access {
                    ::core::option::Option::None => 0,
                    ::core::option::Option::Some(v) => (#code_of) + 1,
                };
                w.write(code, #nbits)?;
            },
            quote!({
                let k = r.read(#nbits)?;
                if k == 0 {
                    ::core::option::Option::None
                } else {
                    let k = k - 1;
                    ::core::option::Option::Some(#value_of)
                }
            }),
        )
    } else {
        (
            quote! {
                let v = #access;
                w.write(#code_of, #nbits)?;
            },
            quote!({
                let k = r.read(#nbits)?;
                #value_of
            }),
        )
    };
    Ok(FieldCode {
        bits: quote!((#nbits as usize)),
        write: quote!({ #write }),
        read,
    })
}

fn expand_struct(input: &DeriveInput, fields: &Fields) -> syn::Result<TokenStream> {
    let name = &input.ident;
    let mut bits = Vec::new();
    let mut writes = Vec::new();
    let mut reads = Vec::new();
    let mut vars = Vec::new();
    for (i, f) in fields.iter().enumerate() {
        let attrs = field_attrs(&f.attrs)?;
        let (label, access) = match &f.ident {
            Some(id) => (id.to_string(), quote!(self.#id)),
            None => {
                let idx = syn::Index::from(i);
                (i.to_string(), quote!(self.#idx))
            }
        };
        let code = field_code(&label, &access, &f.ty, &attrs)?;
        bits.push(code.bits);
        writes.push(code.write);
        let var = format_ident!("f{}", i);
        let read = code.read;
        reads.push(quote!(let #var = #read;));
        vars.push(var);
    }
    let build = match fields {
        Fields::Named(n) => {
            let names = n.named.iter().map(|f| f.ident.as_ref());
            quote!(Self { #(#names: #vars),* })
        }
        Fields::Unnamed(_) => quote!(Self( #(#vars),* )),
        Fields::Unit => quote!(Self),
    };
    let (w, r) = if fields.is_empty() {
        (quote!(_w), quote!(_r))
    } else {
        (quote!(w), quote!(r))
    };
    Ok(quote! {
        impl ::compact::Compact for #name {
            const SIZE_BITS: usize = 0 #(+ #bits)*;
            #[allow(clippy::unnecessary_cast, clippy::cast_lossless)]
            fn write_bits(&self, #w: &mut ::compact::BitWriter<'_>)
                -> ::core::result::Result<(), ::compact::EncodeError> {
                #(#writes)*
                ::core::result::Result::Ok(())
            }
            #[allow(clippy::unnecessary_cast)]
            fn read_bits(#r: &mut ::compact::BitReader<'_>)
                -> ::core::result::Result<Self, ::compact::DecodeError> {
                #(#reads)*
                ::core::result::Result::Ok(#build)
            }
        }
    })
}
