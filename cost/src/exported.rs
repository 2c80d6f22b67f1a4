//! The pipelines of an export folder, from its `manifest.json` and SPIR-V files alone.

use std::path::Path;

use serde_json::Value;

use crate::CostError;
use crate::pipeline::*;

/// Reads a field, or names it in the error.
fn field<'a>(value: &'a Value, name: &str, at: &str) -> Result<&'a Value, CostError> {
    match value.get(name) {
        Some(v) if !v.is_null() => Ok(v),
        _ => Err(CostError::Manifest {
            path: "manifest.json".to_string(),
            message: format!("{at} has no field `{name}`"),
        }),
    }
}

fn string<'a>(value: &'a Value, name: &str, at: &str) -> Result<&'a str, CostError> {
    field(value, name, at)?
        .as_str()
        .ok_or_else(|| CostError::Manifest {
            path: "manifest.json".to_string(),
            message: format!("{at}.{name} is not a string"),
        })
}

fn number(value: &Value, name: &str, at: &str) -> Result<u32, CostError> {
    field(value, name, at)?
        .as_u64()
        .and_then(|n| u32::try_from(n).ok())
        .ok_or_else(|| CostError::Manifest {
            path: "manifest.json".to_string(),
            message: format!("{at}.{name} is not a 32-bit unsigned integer"),
        })
}

fn array<'a>(value: &'a Value, name: &str, at: &str) -> Result<&'a [Value], CostError> {
    field(value, name, at)?
        .as_array()
        .map(Vec::as_slice)
        .ok_or_else(|| CostError::Manifest {
            path: "manifest.json".to_string(),
            message: format!("{at}.{name} is not an array"),
        })
}

/// The SPIR-V words of a file of the export.
fn spirv(dir: &Path, file: &str) -> Result<Vec<u32>, CostError> {
    let path = dir.join(file);
    let bytes = std::fs::read(&path).map_err(|e| CostError::Manifest {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    if bytes.len() % 4 != 0 {
        return Err(CostError::Manifest {
            path: path.display().to_string(),
            message: format!(
                "{} bytes is not a whole number of SPIR-V words",
                bytes.len()
            ),
        });
    }
    Ok(bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect())
}

/// The bindings of one manifest entry point.
fn bindings(entry: &Value, at: &str) -> Result<Vec<BindingDesc>, CostError> {
    array(entry, "bindings", at)?
        .iter()
        .map(|b| {
            let slot = field(b, "spirv", at)?;
            let resource = field(b, "resource", at)?;
            let ty = match string(resource, "kind", at)? {
                "buffer" if resource.get("type") == Some(&Value::from("uniform")) => {
                    DescriptorType::UniformBuffer
                }
                "buffer" => DescriptorType::StorageBuffer,
                "texture" => DescriptorType::SampledImage,
                "storage_texture" => DescriptorType::StorageImage,
                "sampler" => DescriptorType::Sampler,
                other => {
                    return Err(CostError::Manifest {
                        path: "manifest.json".to_string(),
                        message: format!("{at}: resource kind {other:?}"),
                    });
                }
            };
            Ok(BindingDesc {
                set: number(slot, "set", at)?,
                binding: number(slot, "binding", at)?,
                ty,
            })
        })
        .collect()
}

fn vertex_buffers(entry: &Value, at: &str) -> Result<Vec<VertexBufferDesc>, CostError> {
    let Some(buffers) = entry.get("vertex_buffers").and_then(Value::as_array) else {
        return Ok(Vec::new());
    };
    buffers
        .iter()
        .map(|b| {
            Ok(VertexBufferDesc {
                stride: number(b, "array_stride", at)?,
                per_instance: b.get("step_mode") == Some(&Value::from("instance")),
                attributes: array(b, "attributes", at)?
                    .iter()
                    .map(|a| {
                        Ok(AttributeDesc {
                            location: number(a, "shader_location", at)?,
                            format: string(a, "format", at)?.to_string(),
                            offset: number(a, "offset", at)?,
                        })
                    })
                    .collect::<Result<_, CostError>>()?,
            })
        })
        .collect()
}

fn blend(target: &Value, at: &str) -> Result<Option<BlendDesc>, CostError> {
    let Some(blend) = target.get("blend").filter(|b| !b.is_null()) else {
        return Ok(None);
    };
    let pair = |c: &Value| -> Result<(String, String), CostError> {
        Ok((
            string(c, "src_factor", at)?.to_string(),
            string(c, "dst_factor", at)?.to_string(),
        ))
    };
    Ok(Some(BlendDesc {
        color: pair(field(blend, "color", at)?)?,
        alpha: pair(field(blend, "alpha", at)?)?,
    }))
}

/// See [`exported_jobs`](crate::pipeline::exported_jobs).
pub(crate) fn jobs(dir: &Path) -> Result<Vec<Job>, CostError> {
    let path = dir.join("manifest.json");
    let text = std::fs::read_to_string(&path).map_err(|e| CostError::Manifest {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let manifest: Value = serde_json::from_str(&text).map_err(|e| CostError::Manifest {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    let variants = array(&manifest, "variants", "manifest")?;
    let entry_of = |variant: &str, entry: &str| -> Option<&Value> {
        variants
            .iter()
            .find(|v| v.get("name") == Some(&Value::from(variant)))?
            .get("entry_points")?
            .as_array()?
            .iter()
            .find(|e| e.get("name") == Some(&Value::from(entry)))
    };
    let mut jobs = Vec::new();
    for v in variants {
        let variant = string(v, "name", "variants[]")?;
        for e in array(v, "entry_points", variant)? {
            let name = string(e, "name", variant)?;
            let at = format!("{variant}.{name}");
            let stage = StageCode {
                spirv: spirv(dir, string(field(e, "files", &at)?, "spirv", &at)?)?,
                entry: name.to_string(),
            };
            let pipeline = match string(e, "stage", &at)? {
                "compute" => PipelineDesc::Compute {
                    stage,
                    bindings: bindings(e, &at)?,
                },
                "fragment" => {
                    let reference = field(e, "vertex", &at)?;
                    let (vv, ve) = (
                        string(reference, "variant", &at)?,
                        string(reference, "entry", &at)?,
                    );
                    let vertex = entry_of(vv, ve).ok_or_else(|| CostError::Manifest {
                        path: "manifest.json".to_string(),
                        message: format!("{at}.vertex names {vv}.{ve}, which it does not list"),
                    })?;
                    let vat = format!("{vv}.{ve}");
                    let mut all = bindings(e, &at)?;
                    for b in bindings(vertex, &vat)? {
                        if !all.iter().any(|a| a.set == b.set && a.binding == b.binding) {
                            all.push(b);
                        }
                    }
                    let target = array(e, "color_targets", &at)?.first().ok_or_else(|| {
                        CostError::Manifest {
                            path: "manifest.json".to_string(),
                            message: format!("{at}.color_targets is empty"),
                        }
                    })?;
                    let format = array(target, "formats", &at)?
                        .first()
                        .and_then(Value::as_str)
                        .ok_or_else(|| CostError::Manifest {
                            path: "manifest.json".to_string(),
                            message: format!("{at}.color_targets[0].formats is empty"),
                        })?;
                    PipelineDesc::Graphics {
                        vertex: StageCode {
                            spirv: spirv(
                                dir,
                                string(field(vertex, "files", &vat)?, "spirv", &vat)?,
                            )?,
                            entry: ve.to_string(),
                        },
                        fragment: stage,
                        bindings: all,
                        vertex_buffers: vertex_buffers(vertex, &vat)?,
                        color_format: format.to_string(),
                        blend: blend(target, &at)?,
                    }
                }
                _ => continue,
            };
            jobs.push(Job {
                label: at,
                pipeline,
                count_loops: false,
            });
        }
    }
    Ok(jobs)
}
