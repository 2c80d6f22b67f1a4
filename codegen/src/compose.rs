//! Composition of passes with naga_oil under define sets, and validation with naga.

use std::collections::{BTreeMap, HashMap};
use std::sync::Mutex;

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, ComposerError, NagaModuleDescriptor, ShaderDefValue,
};

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};

use crate::CodegenError;
use crate::manifest::{Axis, MODULES, ModuleSource, PassSource};

/// A define set for one pass: boolean defines (`NAME`) and valued defines
/// (`NAME=VALUE`), checked against the pass's axes.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Defines {
    values: BTreeMap<String, Option<u32>>,
}

impl Defines {
    /// A define set of boolean defines only (the prebuilt variants).
    pub fn flags<'a>(names: impl IntoIterator<Item = &'a str>) -> Self {
        Self {
            values: names.into_iter().map(|n| (n.to_string(), None)).collect(),
        }
    }

    /// Parses `NAME` or `NAME=VALUE` items and checks them against the pass: every
    /// define must belong to one of its axes or valued defines, at most one define of
    /// an exclusive axis may be set, and values must be in range.
    pub fn parse(pass: &PassSource, items: &[String]) -> Result<Self, CodegenError> {
        let mut values = BTreeMap::new();
        for item in items {
            let (name, value) = match item.split_once('=') {
                Some((n, v)) => {
                    let parsed = v.trim().parse::<u32>().map_err(|_| {
                        CodegenError::Define(format!(
                            "define {n}: value `{v}` is not an unsigned integer"
                        ))
                    })?;
                    (n.trim().to_string(), Some(parsed))
                }
                None => (item.trim().to_string(), None),
            };
            values.insert(name, value);
        }
        let defines = Self { values };
        defines.check(pass)?;
        Ok(defines)
    }

    fn check(&self, pass: &PassSource) -> Result<(), CodegenError> {
        let valid = valid_defines(pass);
        for (name, value) in &self.values {
            if let Some(flag_axis) = pass
                .axes
                .iter()
                .find(|a| a.defines().contains(&name.as_str()))
            {
                if value.is_some() {
                    return Err(CodegenError::Define(format!(
                        "define {name} of pass {} is a flag and takes no value",
                        pass.name
                    )));
                }
                if let Axis::OneOf(options) = flag_axis {
                    let set: Vec<&str> = options
                        .iter()
                        .copied()
                        .filter(|o| self.values.contains_key(*o))
                        .collect();
                    if set.len() > 1 {
                        return Err(CodegenError::Define(format!(
                            "defines {} of pass {} exclude each other; set at most one",
                            set.join(", "),
                            pass.name
                        )));
                    }
                }
            } else if pass.hooks.iter().any(|h| h.define == name) {
                if value.is_some() {
                    return Err(CodegenError::Define(format!(
                        "define {name} of pass {} is a flag and takes no value",
                        pass.name
                    )));
                }
            } else if let Some(v) = pass.values.iter().find(|v| v.name == name) {
                let value = value.ok_or_else(|| {
                    CodegenError::Define(format!(
                        "define {name} of pass {} needs a value in {}..={}",
                        pass.name, v.min, v.max
                    ))
                })?;
                if value < v.min || value > v.max {
                    return Err(CodegenError::Define(format!(
                        "define {name}={value} of pass {} is out of range {}..={}",
                        pass.name, v.min, v.max
                    )));
                }
            } else {
                return Err(CodegenError::Define(format!(
                    "unknown define {name} for pass {}; valid defines: {}",
                    pass.name,
                    if valid.is_empty() {
                        "none".to_string()
                    } else {
                        valid.join(", ")
                    }
                )));
            }
        }
        Ok(())
    }

    /// Whether the set holds the define `name`.
    pub fn contains(&self, name: &str) -> bool {
        self.values.contains_key(name)
    }

    /// The variant name of this define set: `pass@default` or `pass@A+B=3` with the
    /// `VOLFOG_` prefix dropped, sorted.
    pub fn variant_name(&self, pass: &str) -> String {
        let items = self.as_strings();
        let refs: Vec<&str> = items.iter().map(String::as_str).collect();
        crate::manifest::variant_name(pass, &refs)
    }

    /// The defines as `NAME` / `NAME=VALUE` strings, sorted by name.
    pub fn as_strings(&self) -> Vec<String> {
        self.values
            .iter()
            .map(|(n, v)| match v {
                Some(v) => format!("{n}={v}"),
                None => n.clone(),
            })
            .collect()
    }

    /// The naga_oil shader defs for a pass: these defines plus the defaults of its valued
    /// defines.
    pub fn shader_defs(&self, pass: &PassSource) -> HashMap<String, ShaderDefValue> {
        let mut defs: HashMap<String, ShaderDefValue> = self
            .values
            .iter()
            .map(|(n, v)| {
                let value = match v {
                    Some(v) => ShaderDefValue::UInt(*v),
                    None => ShaderDefValue::Bool(true),
                };
                (n.clone(), value)
            })
            .collect();
        for v in pass.values {
            defs.entry(v.name.to_string())
                .or_insert(ShaderDefValue::UInt(v.default));
        }
        defs
    }
}

/// Every define a pass accepts, for error messages (a hook's define with the user's
/// module it needs).
pub fn valid_defines(pass: &PassSource) -> Vec<String> {
    pass.axes
        .iter()
        .flat_map(|a| a.defines().into_iter().map(|d| d.to_string()))
        .chain(
            pass.values
                .iter()
                .map(|v| format!("{}=<{}..={}>", v.name, v.min, v.max)),
        )
        .chain(
            pass.hooks
                .iter()
                .map(|h| format!("{} (with a module defining {})", h.define, h.function)),
        )
        .collect()
}

/// The import path a module's `#define_import_path` line declares, if any.
pub fn declared_import_path(source: &str) -> Option<&str> {
    source.lines().find_map(|line| {
        line.trim()
            .strip_prefix("#define_import_path")
            .map(|rest| rest.trim())
    })
}

fn render(err: &ComposerError, composer: &Composer) -> CodegenError {
    CodegenError::Compose(err.emit_to_string(composer))
}

/// Adds one module to a composer after checking that its import path matches its file.
pub fn add_module(composer: &mut Composer, module: &ModuleSource) -> Result<(), CodegenError> {
    let found = declared_import_path(module.source).unwrap_or("");
    if found != module.import_path {
        return Err(CodegenError::ImportPath {
            file: module.file.to_string(),
            found: found.to_string(),
            expected: module.import_path.to_string(),
        });
    }
    composer
        .add_composable_module(ComposableModuleDescriptor {
            source: module.source,
            file_path: module.file,
            ..Default::default()
        })
        .map(|_| ())
        .map_err(|e| render(&e, composer))
}

/// Adds every volfog module, in dependency order, to a composer.
pub fn add_all_modules(composer: &mut Composer) -> Result<(), CodegenError> {
    for module in MODULES {
        add_module(composer, module)?;
    }
    Ok(())
}

/// A validating composer holding every volfog module, with the capabilities of
/// [`validate`].
pub fn composer() -> Result<Composer, CodegenError> {
    let mut composer = Composer::default().with_capabilities(CAPABILITIES);
    add_all_modules(&mut composer)?;
    Ok(composer)
}

/// Composes a pass into one naga module under a define set. A hook's define needs the
/// user's module in the composer ([`crate::custom`]).
pub fn compose_pass(
    composer: &mut Composer,
    pass: &PassSource,
    defines: &Defines,
) -> Result<naga::Module, CodegenError> {
    if let Some(hook) = pass
        .hooks
        .iter()
        .find(|h| defines.contains(h.define) && !composer.contains_module(h.import_path))
    {
        return Err(CodegenError::CustomModuleMissing {
            define: hook.define.to_string(),
            signature: hook.signature.to_string(),
        });
    }
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: pass.source,
            file_path: pass.file,
            shader_defs: defines.shader_defs(pass),
            ..Default::default()
        })
        .map_err(|e| render(&e, composer))
}

/// The capabilities modules are validated with: naga's defaults plus multiview.
const CAPABILITIES: Capabilities = Capabilities::MULTISAMPLED_SHADING
    .union(Capabilities::CUBE_ARRAY_TEXTURES)
    .union(Capabilities::MULTIVIEW);

/// Validates a module with every validation flag and the default capabilities plus
/// multiview (`@builtin(view_index)`, which the multiview apply reads); `what` names it
/// in the error.
pub fn validate(module: &naga::Module, what: &str) -> Result<ModuleInfo, CodegenError> {
    Validator::new(ValidationFlags::all(), CAPABILITIES)
        .validate(module)
        .map_err(|e| {
            let mut text = format!("{what}: validation failed: {e}");
            let mut source = std::error::Error::source(e.as_inner());
            while let Some(s) = source {
                text.push_str(&format!(": {s}"));
                source = s.source();
            }
            CodegenError::Validation(text)
        })
}

/// Runs `f` with a process-wide composer that holds every volfog module (built on
/// first use, and built again if a composition panicked while holding it).
pub fn with_shared_composer<T>(
    f: impl FnOnce(&mut Composer) -> Result<T, CodegenError>,
) -> Result<T, CodegenError> {
    static SHARED: Mutex<Option<Composer>> = Mutex::new(None);
    let mut guard = SHARED.lock().unwrap_or_else(|poisoned| {
        let mut guard = poisoned.into_inner();
        *guard = None;
        SHARED.clear_poison();
        guard
    });
    if guard.is_none() {
        *guard = Some(composer()?);
    }
    f(guard.as_mut().expect("built above"))
}

/// Composes a pass under a define set with the shared composer and validates the
/// result: the module a runtime hands to its GPU API.
pub fn compose_validated(
    pass: &PassSource,
    defines: &Defines,
) -> Result<naga::Module, CodegenError> {
    let module = with_shared_composer(|composer| compose_pass(composer, pass, defines))?;
    validate(&module, &defines.variant_name(pass.name))?;
    Ok(module)
}
