//! The JSON shapes shared by spectra and indices: a bare number, or a map with exactly
//! one key naming the kind (`{"sampled": {...}}`). Written by hand (not `untagged`) so
//! that a bad value gets serde's precise message and field path instead of "data did
//! not match any variant".

use crate::error::json_f32::checked;
use serde::Deserializer;
use serde::de::{self, MapAccess, Visitor};
use std::fmt;
use std::marker::PhantomData;

/// A type written as a number or as a one-key map.
pub(crate) trait NumberOrMap<'de>: Sized {
    /// What the JSON should look like, for error messages.
    const EXPECTING: &'static str;
    /// From a bare number.
    fn from_number<E: de::Error>(v: f64) -> Result<Self, E>;
    /// From a map whose first key has not been read yet.
    fn from_map<A: MapAccess<'de>>(map: A) -> Result<Self, A::Error>;
}

/// Deserialize a [`NumberOrMap`] type.
pub(crate) fn number_or_map<'de, D, T>(d: D) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
    T: NumberOrMap<'de>,
{
    struct V<T>(PhantomData<T>);
    impl<'de, T: NumberOrMap<'de>> Visitor<'de> for V<T> {
        type Value = T;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str(T::EXPECTING)
        }
        // A bare number is stored as `f32`: refused where the conversion would overflow
        // to ∞ or flush a non-zero value to zero or a subnormal.
        fn visit_f64<E: de::Error>(self, v: f64) -> Result<T, E> {
            T::from_number(checked(v)?)
        }
        fn visit_i64<E: de::Error>(self, v: i64) -> Result<T, E> {
            T::from_number(checked(v as f64)?)
        }
        fn visit_u64<E: de::Error>(self, v: u64) -> Result<T, E> {
            T::from_number(checked(v as f64)?)
        }
        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<T, A::Error> {
            T::from_map(map)
        }
    }
    d.deserialize_any(V(PhantomData))
}

/// Read the single key of a one-key map (one of `kinds`); the caller reads its value
/// and then calls [`no_more_keys`].
pub(crate) fn kind_key<'de, A: MapAccess<'de>>(
    map: &mut A,
    kinds: &'static [&'static str],
) -> Result<String, A::Error> {
    let key: Option<String> = map.next_key()?;
    match key {
        None => Err(de::Error::custom(format!(
            "an empty map: give one of {}",
            list(kinds)
        ))),
        Some(k) if kinds.contains(&k.as_str()) => Ok(k),
        Some(k) => Err(de::Error::unknown_variant(&k, kinds)),
    }
}

/// Reject a second key after the kind's value.
pub(crate) fn no_more_keys<'de, A: MapAccess<'de>>(
    map: &mut A,
    first: &str,
    kinds: &'static [&'static str],
) -> Result<(), A::Error> {
    match map.next_key::<String>()? {
        None => Ok(()),
        Some(k) => Err(de::Error::custom(format!(
            "`{first}` and `{k}` given: give exactly one of {}",
            list(kinds)
        ))),
    }
}

fn list(kinds: &[&str]) -> String {
    kinds
        .iter()
        .map(|k| format!("`{k}`"))
        .collect::<Vec<_>>()
        .join(", ")
}
