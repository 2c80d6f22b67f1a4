//! A minimal SPIR-V reader: just enough to find the workgroup size of a compute entry point.

use std::collections::HashMap;

use crate::VkError;

/// The SPIR-V magic number (first word of every module, in host byte order).
const MAGIC: u32 = 0x0723_0203;
/// Number of words in the module header.
const HEADER_WORDS: usize = 5;

const OP_ENTRY_POINT: u32 = 15;
const OP_EXECUTION_MODE: u32 = 16;
const OP_CONSTANT: u32 = 43;
const OP_CONSTANT_COMPOSITE: u32 = 44;
const OP_SPEC_CONSTANT: u32 = 50;
const OP_SPEC_CONSTANT_COMPOSITE: u32 = 51;
const OP_DECORATE: u32 = 71;
const OP_EXECUTION_MODE_ID: u32 = 331;

const EXECUTION_MODEL_GL_COMPUTE: u32 = 5;
const EXECUTION_MODE_LOCAL_SIZE: u32 = 17;
const EXECUTION_MODE_LOCAL_SIZE_ID: u32 = 38;
const DECORATION_BUILT_IN: u32 = 11;
const BUILT_IN_WORKGROUP_SIZE: u32 = 25;

/// Returns the workgroup size `[x, y, z]` of the compute (`GLCompute`) entry point named `entry`.
///
/// The size is taken, in SPIR-V's order of precedence, from:
/// 1. a constant decorated `BuiltIn WorkgroupSize` (glslang emits this for
///    `layout(local_size_x_id = N)`; the specialization constants' *default* values are used),
/// 2. `OpExecutionModeId … LocalSizeId` (resolved through `OpConstant` / `OpSpecConstant`),
/// 3. `OpExecutionMode … LocalSize x y z` (what glslang, Slang and naga usually emit).
///
/// Errors with [`VkError::Spirv`] when the words are not a SPIR-V module, when there is no
/// compute entry point of that name, or when its size cannot be determined.
pub fn local_size(spirv: &[u32], entry: &str) -> Result<[u32; 3], VkError> {
    let err = |msg: String| Err(VkError::Spirv(msg));
    if spirv.len() < HEADER_WORDS {
        return err(format!(
            "{} words is shorter than the SPIR-V header",
            spirv.len()
        ));
    }
    if spirv[0] != MAGIC {
        return err(format!(
            "first word {:#010x} is not the SPIR-V magic number {MAGIC:#010x}",
            spirv[0]
        ));
    }

    let mut compute_entries: Vec<(String, u32)> = Vec::new();
    let mut local_sizes: HashMap<u32, [u32; 3]> = HashMap::new();
    let mut local_size_ids: HashMap<u32, [u32; 3]> = HashMap::new();
    let mut constants: HashMap<u32, u32> = HashMap::new();
    let mut composites: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut workgroup_size_id: Option<u32> = None;

    let mut at = HEADER_WORDS;
    while at < spirv.len() {
        let word_count = (spirv[at] >> 16) as usize;
        let opcode = spirv[at] & 0xffff;
        if word_count == 0 || at + word_count > spirv.len() {
            return err(format!(
                "instruction at word {at} has an invalid word count {word_count}"
            ));
        }
        let operands = &spirv[at + 1..at + word_count];
        match opcode {
            OP_ENTRY_POINT if operands.len() >= 3 && operands[0] == EXECUTION_MODEL_GL_COMPUTE => {
                compute_entries.push((literal_string(&operands[2..]), operands[1]));
            }
            OP_EXECUTION_MODE
                if operands.len() >= 5 && operands[1] == EXECUTION_MODE_LOCAL_SIZE =>
            {
                local_sizes.insert(operands[0], [operands[2], operands[3], operands[4]]);
            }
            OP_EXECUTION_MODE_ID
                if operands.len() >= 5 && operands[1] == EXECUTION_MODE_LOCAL_SIZE_ID =>
            {
                local_size_ids.insert(operands[0], [operands[2], operands[3], operands[4]]);
            }
            OP_DECORATE
                if operands.len() >= 3
                    && operands[1] == DECORATION_BUILT_IN
                    && operands[2] == BUILT_IN_WORKGROUP_SIZE =>
            {
                workgroup_size_id = Some(operands[0]);
            }
            OP_CONSTANT | OP_SPEC_CONSTANT if operands.len() >= 3 => {
                // Result type, result id, then the value's low word (sizes are 32-bit integers).
                constants.insert(operands[1], operands[2]);
            }
            OP_CONSTANT_COMPOSITE | OP_SPEC_CONSTANT_COMPOSITE if operands.len() >= 2 => {
                composites.insert(operands[1], operands[2..].to_vec());
            }
            _ => {}
        }
        at += word_count;
    }

    let Some(&(_, entry_id)) = compute_entries.iter().find(|(name, _)| name == entry) else {
        let names: Vec<&str> = compute_entries.iter().map(|(n, _)| n.as_str()).collect();
        return err(format!(
            "no GLCompute entry point named {entry:?} (compute entry points: {names:?})"
        ));
    };
    let resolve = |ids: &[u32]| -> Option<[u32; 3]> {
        match ids {
            [x, y, z] => Some([*constants.get(x)?, *constants.get(y)?, *constants.get(z)?]),
            _ => None,
        }
    };
    if let Some(id) = workgroup_size_id {
        return match composites.get(&id).and_then(|ids| resolve(ids)) {
            Some(size) => Ok(size),
            None => err(format!(
                "the WorkgroupSize built-in %{id} is not a composite of three integer constants"
            )),
        };
    }
    if let Some(ids) = local_size_ids.get(&entry_id) {
        return match resolve(ids) {
            Some(size) => Ok(size),
            None => err(format!(
                "LocalSizeId operands {ids:?} of {entry:?} are not integer constants"
            )),
        };
    }
    match local_sizes.get(&entry_id) {
        Some(size) => Ok(*size),
        None => err(format!(
            "entry point {entry:?} has no LocalSize / LocalSizeId execution mode"
        )),
    }
}

/// Decodes a nul-terminated SPIR-V literal string (UTF-8 packed little-endian into words).
fn literal_string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take_while(|&b| b != 0)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Packs a string the way SPIR-V stores literal strings.
    fn string_words(s: &str) -> Vec<u32> {
        let mut bytes = s.as_bytes().to_vec();
        bytes.push(0);
        while bytes.len() % 4 != 0 {
            bytes.push(0);
        }
        bytes
            .chunks(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    fn inst(opcode: u32, operands: &[u32]) -> Vec<u32> {
        let mut v = vec![((operands.len() as u32 + 1) << 16) | opcode];
        v.extend_from_slice(operands);
        v
    }

    fn module(body: &[Vec<u32>]) -> Vec<u32> {
        let mut words = vec![MAGIC, 0x0001_0000, 0, 100, 0];
        for i in body {
            words.extend_from_slice(i);
        }
        words
    }

    fn entry(model: u32, id: u32, name: &str) -> Vec<u32> {
        let mut ops = vec![model, id];
        ops.extend(string_words(name));
        inst(OP_ENTRY_POINT, &ops)
    }

    #[test]
    fn literal_local_size_of_the_named_entry() {
        let words = module(&[
            entry(EXECUTION_MODEL_GL_COMPUTE, 4, "a"),
            entry(EXECUTION_MODEL_GL_COMPUTE, 5, "main_long_name"),
            inst(OP_EXECUTION_MODE, &[4, EXECUTION_MODE_LOCAL_SIZE, 8, 8, 1]),
            inst(OP_EXECUTION_MODE, &[5, EXECUTION_MODE_LOCAL_SIZE, 64, 1, 1]),
        ]);
        assert_eq!(local_size(&words, "a").unwrap(), [8, 8, 1]);
        assert_eq!(local_size(&words, "main_long_name").unwrap(), [64, 1, 1]);
        let e = local_size(&words, "missing").unwrap_err().to_string();
        assert!(e.contains("main_long_name"), "{e}");
    }

    #[test]
    fn local_size_id_and_workgroup_size_builtin() {
        let ids = module(&[
            entry(EXECUTION_MODEL_GL_COMPUTE, 4, "main"),
            inst(
                OP_EXECUTION_MODE_ID,
                &[4, EXECUTION_MODE_LOCAL_SIZE_ID, 10, 11, 11],
            ),
            inst(OP_CONSTANT, &[9, 10, 32]),
            inst(OP_SPEC_CONSTANT, &[9, 11, 1]),
        ]);
        assert_eq!(local_size(&ids, "main").unwrap(), [32, 1, 1]);

        let builtin = module(&[
            entry(EXECUTION_MODEL_GL_COMPUTE, 4, "main"),
            inst(OP_EXECUTION_MODE, &[4, EXECUTION_MODE_LOCAL_SIZE, 1, 1, 1]),
            inst(
                OP_DECORATE,
                &[20, DECORATION_BUILT_IN, BUILT_IN_WORKGROUP_SIZE],
            ),
            inst(OP_SPEC_CONSTANT, &[9, 10, 128]),
            inst(OP_CONSTANT, &[9, 11, 1]),
            inst(OP_SPEC_CONSTANT_COMPOSITE, &[12, 20, 10, 11, 11]),
        ]);
        assert_eq!(local_size(&builtin, "main").unwrap(), [128, 1, 1]);
    }

    #[test]
    fn rejects_non_spirv_and_non_compute() {
        assert!(local_size(&[], "main").is_err());
        assert!(local_size(&[1, 2, 3, 4, 5], "main").is_err());
        let vertex = module(&[entry(0, 4, "main")]);
        assert!(local_size(&vertex, "main").is_err());
        let truncated = {
            let mut w = module(&[entry(EXECUTION_MODEL_GL_COMPUTE, 4, "main")]);
            w.push(10 << 16 | OP_EXECUTION_MODE);
            w
        };
        assert!(local_size(&truncated, "main").is_err());
    }
}
