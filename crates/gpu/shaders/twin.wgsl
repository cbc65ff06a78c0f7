// needs: sampler
// Twin pixels: the bit-exact mirror of `crates/film/src/twin.rs` `TwinLayout::pixel`.
// Twin k is block (k % blocks_x, k / blocks_x) of side `block`, at a hashed position inside it;
// the kernel renders twins as virtual rows after the film (twin k at row film_rows + k / width,
// column k % width), in replica 1 of the render's seed.
//
// Interface: fn twin_pixel(k: u32) -> vec2u      // params.twin_* layout

fn twin_pixel(k: u32) -> vec2u {
    let block = params.twin_block;
    let bx = k % params.twin_blocks_x;
    let by = k / params.twin_blocks_x;
    let h = sampler_hash_combine(sampler_hash_combine(params.twin_key, bx), by);
    let ox = h % block;
    let oy = (h / block) % block;
    return vec2u(
        min(bx * block + ox, params.camera.width - 1u),
        min(by * block + oy, params.film_rows - 1u),
    );
}
