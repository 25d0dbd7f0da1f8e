//! Textures: binary PPM files named by meshes (`texturecoords N NAME`) and textured
//! triangles (`tt NAME`), read and checked when the scene loads. A name is looked
//! for beside the file that names it, then in a `TextureFiles` folder beside that
//! file's folder (where the distributed BART scenes keep them: `kitchen/aff/*.aff`
//! name `kitchen/TextureFiles/*.ppm`). Each file is read once.

use std::io::Read as _;
use std::path::PathBuf;

use super::parser::{invalid, FileParser, Loc};
use super::scene::{Location, Texture};
use crate::image::decode_ppm_raster;
use crate::limits::MAX_TEXTURE_TEXELS;
use crate::nff::ParseError;

/// The folder beside a scene file's folder where BART's scenes keep their textures.
const TEXTURE_FOLDER: &str = "TextureFiles";

impl FileParser<'_, '_, '_> {
    /// The texture `name`, named at `at`: its index in the scene's textures, read
    /// now if it was not before. A missing file, or one that is not an 8-bit binary
    /// PPM of at most [`MAX_TEXTURE_TEXELS`] texels, is an error at `at`.
    pub(super) fn texture(&mut self, name: &str, at: Loc) -> Result<u32, ParseError> {
        let candidates = [
            self.dir.join(name),
            self.dir.join("..").join(TEXTURE_FOLDER).join(name),
        ];
        let Some(path) = candidates.iter().find(|p| p.is_file()) else {
            let [a, b] = candidates.map(|p| p.display().to_string());
            return Err(invalid(
                at,
                format!("texture {name} not found (looked for {a} and {b})"),
            ));
        };
        if let Some(&id) = self.b.texture_paths.get(path) {
            return Ok(id);
        }
        let texture = read_texture(name, path, at)?;
        if texture.1 > 0 {
            let at = Location {
                file: self.file,
                line: at.0,
                column: at.1,
            };
            let message = format!("texture {name}: {} bytes after its image ignored", texture.1);
            self.b.warn(at, message);
        }
        let id = self.b.scene.textures.len() as u32;
        self.b.scene.textures.push(Texture {
            at: Location {
                file: self.file,
                line: at.0,
                column: at.1,
            },
            ..texture.0
        });
        self.b.texture_paths.insert(path.clone(), id);
        Ok(id)
    }
}

/// The texture in `path`, and the number of bytes after its image that matter (a
/// single final line break, which some writers add, does not).
fn read_texture(name: &str, path: &PathBuf, at: Loc) -> Result<(Texture, usize), ParseError> {
    let shown = path.display();
    let most = MAX_TEXTURE_TEXELS * 3 + 4096;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(most).read_to_end(&mut bytes))
        .map_err(|e| {
            invalid(
                at,
                format!("cannot read texture {name} ({shown}): {}", crate::io_reason(&e)),
            )
        })?;
    let ppm = decode_ppm_raster(&bytes, MAX_TEXTURE_TEXELS)
        .map_err(|e| invalid(at, format!("texture {name} ({shown}) is not a usable PPM: {e}")))?;
    if ppm.width == 0 || ppm.height == 0 {
        return Err(invalid(at, format!("texture {name} ({shown}) has no texels")));
    }
    let extra = match ppm.trailing {
        1 if bytes.last().is_some_and(u8::is_ascii_whitespace) => 0,
        n => n,
    };
    let image = crate::image::Texture::new(ppm.width, ppm.height, ppm.rgb)
        .ok_or_else(|| invalid(at, format!("texture {name} ({shown}) has no texels")))?;
    let texture = Texture {
        name: name.to_string(),
        path: path.clone(),
        image: std::sync::Arc::new(image),
        at: Location::default(),
    };
    Ok((texture, extra))
}
