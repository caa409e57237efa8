// The material of the current draw, from the raster push constants.
Surface draw_surface() {
    return Surface(draw.color_ka.rgb, draw.color_ka.a, draw.kd_ks_p.x, draw.kd_ks_p.y, draw.kd_ks_p.z);
}
