//! Readable names for exported shaders.
//!
//! naga_oil gives every item it imports a decorated name,
//! `<item>X_naga_oil_mod_X<base32 of the module path>X`. Exports restore the plain
//! item name; where two items would then share a name, both are qualified with the
//! last segment of their module path (`phase_PI`), and a collision that remains is an
//! error rather than a silent renaming by a backend.

use std::collections::HashMap;

use crate::CodegenError;

const DECORATION_PRE: &str = "X_naga_oil_mod_X";

/// Splits a decorated name into (item, module path); `None` for plain names.
pub fn undecorate(name: &str) -> Option<(String, String)> {
    let start = name.find(DECORATION_PRE)?;
    let encoded = name[start + DECORATION_PRE.len()..].strip_suffix('X')?;
    let module = base32_decode(encoded)?;
    Some((name[..start].to_string(), module))
}

/// RFC 4648 base32 without padding (the alphabet naga_oil uses).
fn base32_decode(text: &str) -> Option<String> {
    let mut bits: u64 = 0;
    let mut count = 0u32;
    let mut out = Vec::new();
    for c in text.bytes() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'2'..=b'7' => c - b'2' + 26,
            _ => return None,
        };
        bits = (bits << 5) | u64::from(v);
        count += 5;
        if count >= 8 {
            count -= 8;
            out.push((bits >> count) as u8);
            bits &= (1 << count) - 1;
        }
    }
    String::from_utf8(out).ok()
}

#[derive(Clone, Copy)]
enum Slot {
    Type(naga::Handle<naga::Type>),
    Constant(naga::Handle<naga::Constant>),
    Override(naga::Handle<naga::Override>),
    Global(naga::Handle<naga::GlobalVariable>),
    Function(naga::Handle<naga::Function>),
}

struct Item {
    slot: Slot,
    plain: String,
    qualified: Option<String>,
}

/// Replaces naga_oil's decorated names in a module with readable ones.
pub fn make_readable(module: &mut naga::Module, variant: &str) -> Result<(), CodegenError> {
    let mut items = Vec::new();
    let mut push = |slot: Slot, name: &Option<String>| {
        if let Some(name) = name {
            let (plain, qualified) = match undecorate(name) {
                Some((item, path)) => {
                    let stem = path.rsplit("::").next().unwrap_or(&path).to_string();
                    (item.clone(), Some(format!("{stem}_{item}")))
                }
                None => (name.clone(), None),
            };
            items.push(Item {
                slot,
                plain,
                qualified,
            });
        }
    };
    for (h, t) in module.types.iter() {
        push(Slot::Type(h), &t.name);
    }
    for (h, c) in module.constants.iter() {
        push(Slot::Constant(h), &c.name);
    }
    for (h, o) in module.overrides.iter() {
        push(Slot::Override(h), &o.name);
    }
    for (h, g) in module.global_variables.iter() {
        push(Slot::Global(h), &g.name);
    }
    for (h, f) in module.functions.iter() {
        push(Slot::Function(h), &f.name);
    }
    let entry_names: Vec<String> = module.entry_points.iter().map(|e| e.name.clone()).collect();

    let mut uses: HashMap<&str, usize> = HashMap::new();
    for item in &items {
        *uses.entry(item.plain.as_str()).or_default() += 1;
    }
    for name in &entry_names {
        *uses.entry(name.as_str()).or_default() += 1;
    }
    let mut chosen: Vec<String> = Vec::with_capacity(items.len());
    for item in &items {
        let name = match (&item.qualified, uses[item.plain.as_str()] > 1) {
            (Some(q), true) => q.clone(),
            _ => item.plain.clone(),
        };
        chosen.push(name);
    }
    let mut seen: HashMap<&str, usize> = HashMap::new();
    for (i, name) in chosen.iter().enumerate() {
        if let Some(j) = seen.insert(name.as_str(), i) {
            return Err(CodegenError::NameCollision {
                variant: variant.to_string(),
                detail: format!(
                    "`{name}` names both `{}` and `{}`",
                    items[j].plain, items[i].plain
                ),
            });
        }
    }
    for name in &entry_names {
        if let Some(&i) = seen.get(name.as_str()) {
            return Err(CodegenError::NameCollision {
                variant: variant.to_string(),
                detail: format!("entry point `{name}` collides with `{}`", items[i].plain),
            });
        }
    }
    for (item, name) in items.iter().zip(chosen) {
        if item.qualified.is_none() && name == item.plain {
            continue;
        }
        match item.slot {
            Slot::Type(h) => {
                let inner = module.types[h].inner.clone();
                module.types.replace(
                    h,
                    naga::Type {
                        name: Some(name),
                        inner,
                    },
                );
            }
            Slot::Constant(h) => module.constants.get_mut(h).name = Some(name),
            Slot::Override(h) => module.overrides.get_mut(h).name = Some(name),
            Slot::Global(h) => module.global_variables.get_mut(h).name = Some(name),
            Slot::Function(h) => module.functions.get_mut(h).name = Some(name),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn undecorates_naga_oil_names() {
        // "volfog::phase" in base32 without padding.
        let decorated = "phase_hgX_naga_oil_mod_XOZXWYZTPM45DU4DIMFZWKX";
        let (item, module) = undecorate(decorated).expect("decorated");
        assert_eq!(item, "phase_hg");
        assert_eq!(module, "volfog::phase");
        assert!(undecorate("plain_name").is_none());
    }
}
