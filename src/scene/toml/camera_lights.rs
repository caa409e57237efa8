//! `[camera]`, `[lighting]` and `[[lights]]`: a camera that can see (a
//! view direction, an up vector not along it, a field of view `f32` can
//! place at the image's height) and lights of non-negative intensity.

use glam::DVec3;
use toml::Spanned;

use super::checks::{spanned_map, Ctx};
use super::schema::{v3, CameraRaw, LightRaw, LightingRaw};
use crate::scene::defaults::DEFAULT_FOV_Y_DEG;
use crate::scene::error::SceneError;
use crate::scene::model::{Camera, Falloff, ImageSettings, Lighting, PointLight};

/// The camera, refused where it cannot see: `look_at` at `position`, a
/// zero `up` or one along the view, `fov_y` outside (0, 180).
pub(super) fn camera(cx: &Ctx, cam: &CameraRaw) -> Result<Camera, SceneError> {
    let position = v3(cam.position.get_ref());
    let look_at = v3(cam.look_at.get_ref());
    let up = cam.up.as_ref().map_or(DVec3::Y, |u| v3(u.get_ref()));
    let dir = look_at - position;
    let scale = position.abs().max(look_at.abs()).max_element().max(1.0);
    if dir.length() <= 1e-12 * scale {
        return Err(cx.err(
            &cam.look_at,
            "`look_at` equals the camera `position`; expected a point the camera looks toward",
        ));
    }
    if let Some(u) = &cam.up {
        if up.length() == 0.0 {
            return Err(cx.err(
                u,
                "`up` is the zero vector; expected a direction such as [0, 1, 0]",
            ));
        }
    }
    if up.normalize().cross(dir.normalize()).length() < 1e-9 {
        let at = cam
            .up
            .as_ref()
            .map_or_else(|| cx.line(&cam.look_at), |u| cx.line(u));
        return Err(SceneError::invalid(
            cx.label,
            at,
            "camera `up` is parallel to the view direction (look_at - position); expected an up vector that is not",
        ));
    }
    let fov_y_deg = match &cam.fov_y {
        Some(f) => {
            let v = f.get_ref().0;
            if !(v > 0.0 && v < 180.0) {
                return Err(cx.err(
                    f,
                    format!("`fov_y` is {v}; expected degrees strictly between 0 and 180"),
                ));
            }
            v
        }
        None => DEFAULT_FOV_Y_DEG,
    };
    Ok(Camera {
        position,
        look_at,
        up: up.normalize(),
        fov_y_deg,
    })
}

/// A view too narrow for f32 at this height (`narrow_view`), refused at
/// the line of `fov_y` (or of `position` where the default is too narrow).
pub(super) fn refuse_narrow_view(
    cx: &Ctx,
    cam: &CameraRaw,
    camera: &Camera,
    image: &ImageSettings,
) -> Result<(), SceneError> {
    if let Some(why) = crate::narrow_view::refusal(camera.fov_y_deg, image.height) {
        let at = cam
            .fov_y
            .as_ref()
            .map_or_else(|| cx.line(&cam.position), |f| cx.line(f));
        return Err(SceneError::invalid(cx.label, at, why));
    }
    Ok(())
}

/// `[lighting]`, the defaults where it or a key is absent.
pub(super) fn lighting(cx: &Ctx, raw: Option<&LightingRaw>) -> Result<Lighting, SceneError> {
    let mut lighting = Lighting::default();
    if let Some(l) = raw {
        if let Some(a) = &l.ambient {
            lighting.ambient =
                cx.non_negative3(&spanned_map(a, |x| x.splat()), "lighting.ambient")?;
        }
        if let Some(k) = &l.k {
            lighting.k = cx.non_negative(k, "lighting.k")?;
        }
        if let Some(i) = l.interpolation {
            lighting.interpolation = i;
        }
        if let Some(a) = l.attenuation {
            lighting.falloff = if a { Falloff::Lecture } else { Falloff::None };
        }
        if let Some(f) = &l.falloff {
            let falloff = *f.get_ref();
            if let Some(a) = l.attenuation.filter(|&a| a != (falloff != Falloff::None)) {
                return Err(cx.err(
                    f,
                    format!(
                        "`lighting.falloff = \"{}\"` contradicts `lighting.attenuation = {a}`; give `falloff` alone",
                        falloff.name()
                    ),
                ));
            }
            lighting.falloff = falloff;
        }
    }
    Ok(lighting)
}

/// `[[lights]]`, in file order.
pub(super) fn lights(cx: &Ctx, raw: &[Spanned<LightRaw>]) -> Result<Vec<PointLight>, SceneError> {
    let mut lights = Vec::with_capacity(raw.len());
    for light in raw {
        let l = light.get_ref();
        let intensity = cx.non_negative3(&spanned_map(&l.intensity, |x| x.splat()), "intensity")?;
        lights.push(PointLight {
            position: v3(&l.position),
            intensity,
        });
    }
    Ok(lights)
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;

    #[test]
    fn camera_must_be_usable() {
        let e = parse_err("[camera]\nposition = [1, 2, 3]\nlook_at = [1, 2, 3]\n");
        assert_has(&e, &["line 3", "`look_at`", "position"]);
        let e = parse_err("[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\n");
        assert_has(&e, &["parallel", "up"]);
        let e = parse_err("[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 0]\n");
        assert_has(&e, &["line 4", "`up`", "zero"]);
        for fov in ["0", "180", "-5", "200"] {
            let e = parse_err(&format!("{CAMERA}fov_y = {fov}\n"));
            assert_has(&e, &["line 4", "`fov_y`", "0 and 180"]);
        }
    }

    #[test]
    fn absurd_and_invalid_values() {
        for (rest, parts) in [
            (
                "[lighting]\nk = -1\n",
                &["line 5", "lighting.k", ">= 0"][..],
            ),
            (
                "[[lights]]\nposition = [0, 0, 0]\nintensity = -2\n",
                &["line 6", "intensity", ">= 0"],
            ),
        ] {
            let e = parse_err(&with_camera(rest));
            assert_has(&e, parts);
        }
    }
}
