//! Uniform and storage buffer bytes in the WGSL layouts (encase).

use encase::ShaderType;

/// Serialises any uniform struct with encase's uniform-buffer layout.
pub fn to_uniform_bytes<T: ShaderType + encase::internal::WriteInto>(value: &T) -> Vec<u8> {
    let mut buffer = encase::UniformBuffer::new(Vec::new());
    buffer
        .write(value)
        .expect("writing into a growable Vec cannot fail");
    buffer.into_inner()
}

/// Serialises a runtime-sized array with encase's storage-buffer layout (at least one
/// element is written so the buffer is never empty).
pub fn to_storage_bytes<T>(values: &[T]) -> Vec<u8>
where
    T: ShaderType + encase::internal::WriteInto + encase::ShaderSize + Default + Clone,
{
    let items: Vec<T> = if values.is_empty() {
        vec![T::default()]
    } else {
        values.to_vec()
    };
    let mut buffer = encase::StorageBuffer::new(Vec::new());
    buffer
        .write(&items)
        .expect("writing into a growable Vec cannot fail");
    buffer.into_inner()
}
