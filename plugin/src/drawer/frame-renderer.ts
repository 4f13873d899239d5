/**
 * Frame composition, in three steps: the base layers (opaque), the lens layer (into the lens
 * target, then composited inside the lens circle with its opacity), then the annotation overlays
 * (premultiplied source-over, everywhere or only inside or outside the lens). Owns the GL passes
 * of one context; knows nothing of OpenSeadragon (the drawer describes the frame).
 */
import type { ResolvedLayer } from '../layers/resolved-layer';
import type { AnnotationDisplay } from '../lens/lens-state';
import type { Light } from '../math/light';
import type { Mat3 } from '../math/matrix';
import type { RenderMode } from '../render/modes';
import type { RenderParams } from '../render/params';
import type { DrawerLens } from './compositor';
import { LayerPass, type ScissorBox, type TileQuad } from './layer-pass';
import { LensTarget, type DeviceCircle } from './lens-target';
import { OverlayPass } from './overlay-pass';
import { createSamplers } from './plane-texture';

/** One item of a frame: its tiles (coarse level first) and its matrix (view × item rotation). */
export interface FrameItem<T> {
  readonly tiles: readonly T[];
  readonly matrix: Mat3;
}

/** A relightable item of a frame. */
export interface FrameLayer<T> extends FrameItem<T> {
  readonly layer: ResolvedLayer;
}

/** What to draw in one frame. */
export interface Frame<T> {
  /** The base layers, in world order. */
  readonly layers: readonly FrameLayer<T>[];
  /** The lens layer, if one is visible. */
  readonly lensLayer: FrameLayer<T> | null;
  readonly overlays: readonly FrameItem<T>[];
  /** A tile's quad under its item's matrix, or null when it has no texture (called at draw time). */
  quadOf(tile: T, itemMatrix: Mat3): TileQuad | null;
  readonly mode: RenderMode;
  readonly params: RenderParams;
  readonly light: Light;
  /** The lens and its circle in device px, y up (both null when the lens is off). */
  readonly lens: DrawerLens | null;
  readonly circle: DeviceCircle | null;
  readonly overlayDisplay: AnnotationDisplay;
  /** Linear (true) or nearest sampling of the planes. */
  readonly smoothing: boolean;
}

/** The passes of one GL context. */
export class FrameRenderer {
  private readonly layerPass: LayerPass;
  private readonly samplers: { linear: WebGLSampler; nearest: WebGLSampler };
  private lensTarget: LensTarget | null = null;
  private overlayPass: OverlayPass | null = null;

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.layerPass = new LayerPass(gl);
    this.samplers = createSamplers(gl);
  }

  /**
   * Compile the programs a layer needs in a mode now.
   *
   * @throws {@link ShaderError} or {@link FloatTargetsUnavailableError}
   */
  prepare(layer: ResolvedLayer, mode: RenderMode, params: RenderParams): void {
    this.layerPass.prepare(layer, mode, params);
  }

  /** Draw a frame onto the canvas. */
  render<T>(frame: Frame<T>): void {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
    gl.disable(gl.BLEND);
    gl.disable(gl.DEPTH_TEST);
    gl.disable(gl.SCISSOR_TEST); // in case the previous frame stopped half-way
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    for (const item of frame.layers) {
      this.drawLayer(frame, item, frame.mode, frame.params, null, null);
    }
    const { lens, circle, lensLayer } = frame;
    if (lens && circle && lensLayer && lens.opacity > 0) {
      this.lensTarget ??= new LensTarget(gl);
      this.lensTarget.drawLens(circle, lens.opacity, (target, box) => {
        this.drawLayer(frame, lensLayer, lens.mode, lens.params, target, box);
      });
    }
    if (frame.overlays.length > 0) {
      this.drawOverlays(frame);
    }
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, null);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindSampler(0, null);
  }

  /** Forget the GL objects after a context loss (they went with the context). */
  forget(): void {
    this.layerPass.forget();
  }

  /** Free the programs and targets. */
  destroy(): void {
    this.layerPass.destroy();
    this.lensTarget?.destroy();
    this.overlayPass?.destroy();
  }

  private sampler(frame: Frame<unknown>): WebGLSampler {
    return frame.smoothing ? this.samplers.linear : this.samplers.nearest;
  }

  /** Relight one item into `target` (null = the canvas); `box` scissors the final stage. */
  private drawLayer<T>(frame: Frame<T>, item: FrameLayer<T>, mode: RenderMode, params: RenderParams,
    target: WebGLFramebuffer | null, box: ScissorBox | null): void {
    this.layerPass.draw({
      layer: item.layer, mode, params, light: frame.light, tiles: item.tiles, target, box,
      quadOf: (tile) => frame.quadOf(tile, item.matrix),
      sampler: this.sampler(frame),
    });
  }

  /** Draw overlay tiles over the frame, masked by the lens. */
  private drawOverlays<T>(frame: Frame<T>): void {
    const quads: TileQuad[] = [];
    for (const { tiles, matrix } of frame.overlays) {
      for (const tile of tiles) {
        const quad = frame.quadOf(tile, matrix);
        if (quad) {
          quads.push(quad);
        }
      }
    }
    this.overlayPass ??= new OverlayPass(this.gl);
    this.overlayPass.draw(quads, frame.circle, frame.overlayDisplay, frame.smoothing);
  }
}
