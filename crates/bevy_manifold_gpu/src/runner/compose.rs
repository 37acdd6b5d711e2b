//! The tracer's WGSL composed as Bevy's pipeline cache composes it: the
//! import modules added to naga_oil's composer, then the entry module,
//! with the scene's shader defs.

use super::GpuTracer;
use crate::shader_defs::TraceDefs;
use crate::{GpuError, RENDER_WGSL};

impl GpuTracer {
    /// The composed, validated shader for a specialisation.
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose(defs: &TraceDefs) -> Result<naga::Module, GpuError> {
        Self::compose_with(&defs.names(), &defs.values())
    }

    /// The shader composed with these shader defs on (those of a
    /// [`TraceDefs`], and `ENCODE_SRGB` as the render pass may add) and
    /// these value defs (`FACE_COUNT`, [`TraceDefs::values`]): the
    /// import modules ([`crate::SHADER_IMPORTS`]) added to naga_oil's
    /// composer, then the entry module, as Bevy's pipeline cache does.
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose_with(names: &[&'static str], values: &[(&'static str, u32)]) -> Result<naga::Module, GpuError> {
        Self::compose_modules(&crate::SHADER_IMPORTS, RENDER_WGSL, names, values)
    }

    /// `entry` composed with these import modules (each after those it
    /// imports), these shader defs on and these value defs: what
    /// [`Self::compose_with`] does
    /// with the tracer's own modules, open to a changed module (the
    /// contract test's deliberately broken copy).
    ///
    /// # Errors
    /// [`GpuError::Shader`] when composition fails.
    pub fn compose_modules(
        imports: &[crate::WgslModule],
        entry: crate::WgslModule,
        names: &[&'static str],
        values: &[(&'static str, u32)],
    ) -> Result<naga::Module, GpuError> {
        use naga_oil::compose::{
            ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue, ShaderLanguage, ShaderType,
        };
        let mut composer = Composer::default();
        let fail = |composer: &Composer, e: naga_oil::compose::ComposerError| GpuError::Shader {
            defs: names.to_vec(),
            message: e.emit_to_string(composer),
        };
        for module in imports {
            let added = composer
                .add_composable_module(ComposableModuleDescriptor {
                    source: module.source,
                    file_path: module.path,
                    language: ShaderLanguage::Wgsl,
                    ..Default::default()
                })
                .map(|_| ());
            added.map_err(|e| fail(&composer, e))?;
        }
        let shader_defs = names
            .iter()
            .map(|n| (n.to_string(), ShaderDefValue::Bool(true)))
            .chain(values.iter().map(|&(n, v)| (n.to_string(), ShaderDefValue::UInt(v))))
            .collect();
        composer
            .make_naga_module(NagaModuleDescriptor {
                source: entry.source,
                file_path: entry.path,
                shader_type: ShaderType::Wgsl,
                shader_defs,
                additional_imports: &[],
            })
            .map_err(|e| fail(&composer, e))
    }

    pub(super) fn shader(&self, defs: &TraceDefs) -> Result<wgpu::ShaderModule, GpuError> {
        let module = Self::compose(defs)?;
        Ok(self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("render.wgsl"),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        }))
    }
}
