#!/usr/bin/python3
"""Trains the single-class CenterNet-style detector of one object and exports ONNX.

Input: a folder with train/ and val/ datasets written by `aerograsp dataset`
(images/NNNNNN.png are the 160x120 network inputs, labels.csv the boxes in
those pixels). Output: an ONNX file (opset 11) of Conv/BatchNorm/ReLU/Resize/
Concat only, which OpenCV 4.6's dnn runs; its single output is 1x5x30x40:
heatmap logit, centre offset x, y (cells), log box width, height (cells);
box decoding lives in C++ (detection/box_detector.cpp).

Run through scripts/train_detectors.sh (which installs python3-torch with apt
and renders the data). Deterministic for a given seed: one thread, seeded
torch and numpy, no data-loader workers.
Run with Debian's /usr/bin/python3 (a pyenv python3 cannot see python3-torch).
"""
import argparse
import csv
import math
import os
import time

import cv2
import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

STRIDE = 4
W_IN, H_IN = 160, 120
W_OUT, H_OUT = W_IN // STRIDE, H_IN // STRIDE


def load_dataset(folder, min_pixels=0, min_coverage=0.0):
    """Images and boxes (None: the object is not in view). With min_pixels or min_coverage, images
    whose object shows fewer than min_pixels pixels (640x480) but some, or is in view with a
    coverage (labels.csv: the share of its front-facing model points the depth shows) below
    min_coverage, are left out: neither a box nor a clean negative."""
    images, boxes = [], []
    with open(os.path.join(folder, "labels.csv")) as f:
        for row in csv.DictReader(f):
            pixels = int(row["object_pixels"])
            if 0 < pixels < min_pixels:
                continue
            if min_coverage > 0.0 and pixels > 0 and float(row["coverage"]) < min_coverage:
                continue
            bgr = cv2.imread(os.path.join(folder, "images", "%06d.png" % int(row["index"])), cv2.IMREAD_COLOR)
            if bgr is None or bgr.shape[:2] != (H_IN, W_IN):
                raise SystemExit("%s: image %s missing or not %dx%d" % (folder, row["index"], W_IN, H_IN))
            images.append(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
            if int(row["visible"]):
                boxes.append([float(row[k]) for k in ("x0", "y0", "x1", "y1")])
            else:
                boxes.append(None)
    return np.stack(images), boxes


def conv(cin, cout, stride=1, dilation=1):
    return nn.Sequential(
        nn.Conv2d(cin, cout, 3, stride, padding=dilation, dilation=dilation, bias=False),
        nn.BatchNorm2d(cout), nn.ReLU(inplace=True))


class Net(nn.Module):
    """Stride-8 backbone with dilated context, upsampled to stride 4 and fused."""

    def __init__(self):
        super().__init__()
        self.s2 = conv(3, 8, 2)     # 60x80
        self.s4 = conv(8, 16, 2)    # 30x40
        self.s8 = conv(16, 32, 2)   # 15x20
        # Dilated context: the receptive field covers the whole 160x120 input (near objects fill it).
        self.ctx = nn.Sequential(conv(32, 32, dilation=2), conv(32, 32, dilation=4), conv(32, 32, dilation=8))
        self.fuse = conv(32 + 16, 16)
        self.head = nn.Conv2d(16, 5, 1)
        nn.init.constant_(self.head.bias, 0.0)
        with torch.no_grad():
            self.head.bias[0] = -4.0  # start with a low heatmap (focal-loss prior)

    def forward(self, x):
        f4 = self.s4(self.s2(x))
        f8 = self.ctx(self.s8(f4))
        up = F.interpolate(f8, scale_factor=2.0, mode="nearest")
        return self.head(self.fuse(torch.cat([up, f4], 1)))


def targets(boxes, size_radius=0):
    """Heatmaps (Gaussian at the centre cell), and regression targets + masks: the offset at the
    centre cell, the log size at the cells within size_radius of it (a peak one cell off the
    centre then still gives the right size)."""
    n = len(boxes)
    heat = np.zeros((n, 1, H_OUT, W_OUT), np.float32)
    reg = np.zeros((n, 4, H_OUT, W_OUT), np.float32)
    mask = np.zeros((n, 1, H_OUT, W_OUT), np.float32)
    size_mask = np.zeros((n, 1, H_OUT, W_OUT), np.float32)
    ys, xs = np.mgrid[0:H_OUT, 0:W_OUT]
    for i, b in enumerate(boxes):
        if b is None:
            continue
        cx, cy = 0.5 * (b[0] + b[2]) / STRIDE, 0.5 * (b[1] + b[3]) / STRIDE
        w, h = max(0.25, (b[2] - b[0]) / STRIDE), max(0.25, (b[3] - b[1]) / STRIDE)
        ix, iy = min(W_OUT - 1, max(0, int(cx))), min(H_OUT - 1, max(0, int(cy)))
        sigma = max(0.5, 0.15 * math.sqrt(w * h))
        heat[i, 0] = np.exp(-((xs - ix) ** 2 + (ys - iy) ** 2) / (2 * sigma * sigma))
        reg[i, :, iy, ix] = [cx - ix, cy - iy, math.log(w), math.log(h)]
        mask[i, 0, iy, ix] = 1.0
        y0, y1 = max(0, iy - size_radius), min(H_OUT, iy + size_radius + 1)
        x0, x1 = max(0, ix - size_radius), min(W_OUT, ix + size_radius + 1)
        reg[i, 2, y0:y1, x0:x1] = math.log(w)
        reg[i, 3, y0:y1, x0:x1] = math.log(h)
        size_mask[i, 0, y0:y1, x0:x1] = 1.0
    return torch.from_numpy(heat), torch.from_numpy(reg), torch.from_numpy(mask), torch.from_numpy(size_mask)


def focal_loss(logits, heat):
    p = torch.sigmoid(logits).clamp(1e-4, 1 - 1e-4)
    pos = heat.eq(1).float()
    neg = 1.0 - pos
    pos_loss = torch.log(p) * (1 - p) ** 2 * pos
    neg_loss = torch.log(1 - p) * p ** 2 * (1 - heat) ** 4 * neg
    npos = pos.sum().clamp(min=1.0)
    return -(pos_loss.sum() + neg_loss.sum()) / npos


def augment(batch, boxes, rng):
    """Flips, brightness/contrast/colour jitter, noise (numpy, uint8 -> float)."""
    out = batch.astype(np.float32) / 255.0
    new_boxes = []
    for i in range(out.shape[0]):
        b = boxes[i]
        if rng.random() < 0.5:
            out[i] = out[i, :, ::-1]
            if b is not None:
                b = [W_IN - b[2], b[1], W_IN - b[0], b[3]]
        gain = rng.uniform(0.6, 1.4) * rng.uniform(0.85, 1.15, size=3)
        out[i] = out[i] * gain + rng.uniform(-0.1, 0.1)
        out[i] += rng.normal(0, 0.02, size=out[i].shape)
        new_boxes.append(b)
    return np.clip(out, 0, 1), new_boxes


def decode(out):
    """Top peak per image, as a box in input pixels and its score (mirrors the C++ decoder)."""
    results = []
    for o in out:
        heat = o[0]
        i = int(np.argmax(heat))
        y, x = divmod(i, W_OUT)
        score = 1.0 / (1.0 + math.exp(-heat[y, x]))
        cx, cy = (x + np.clip(o[1, y, x], 0, 1)) * STRIDE, (y + np.clip(o[2, y, x], 0, 1)) * STRIDE
        w, h = math.exp(np.clip(o[3, y, x], -3, 4)) * STRIDE, math.exp(np.clip(o[4, y, x], -3, 4)) * STRIDE
        results.append((score, [cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2]))
    return results


def iou(a, b):
    ix = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    iy = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    inter = ix * iy
    union = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - inter
    return inter / union if union > 0 else 0.0


def evaluate(net, images, boxes, threshold=0.3):
    net.eval()
    hits, visible, false_pos, negatives, ious = 0, 0, 0, 0, []
    with torch.no_grad():
        for s in range(0, len(images), 64):
            x = torch.from_numpy(images[s:s + 64].astype(np.float32) / 255.0).permute(0, 3, 1, 2)
            for (score, box), truth in zip(decode(net(x).numpy()), boxes[s:s + 64]):
                if truth is None:
                    negatives += 1
                    false_pos += score >= threshold
                else:
                    visible += 1
                    v = iou(box, truth) if score >= threshold else 0.0
                    ious.append(v)
                    hits += v >= 0.5
    net.train()
    return dict(recall=hits / max(1, visible), mean_iou=float(np.mean(ious)) if ious else 0.0,
                false_positive_rate=false_pos / max(1, negatives), visible=visible, negatives=negatives)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", required=True, help="folder with train/ and val/ from `aerograsp dataset`")
    ap.add_argument("--out", required=True, help="ONNX file to write")
    ap.add_argument("--epochs", type=int, default=15)
    ap.add_argument("--batch", type=int, default=32)
    ap.add_argument("--lr", type=float, default=3e-3)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--size-radius", type=int, default=0,
                    help="also train the box size at cells this far (Chebyshev) from the centre cell")
    ap.add_argument("--min-pixels", type=int, default=0,
                    help="leave out training images whose object shows fewer pixels (640x480) than this, but some")
    ap.add_argument("--min-coverage", type=float, default=0.0,
                    help="leave out training images whose object is in view but less of it shows (labels.csv coverage)")
    args = ap.parse_args()

    torch.set_num_threads(1)
    torch.manual_seed(args.seed)
    torch.use_deterministic_algorithms(True)
    rng = np.random.default_rng(args.seed)

    train_images, train_boxes = load_dataset(os.path.join(args.data, "train"), args.min_pixels, args.min_coverage)
    val_images, val_boxes = load_dataset(os.path.join(args.data, "val"))
    net = Net()
    params = sum(p.numel() for p in net.parameters())
    print("train %d images, val %d, %d parameters" % (len(train_images), len(val_images), params), flush=True)
    opt = torch.optim.AdamW(net.parameters(), lr=args.lr, weight_decay=1e-4)
    steps = args.epochs * math.ceil(len(train_images) / args.batch)
    sched = torch.optim.lr_scheduler.OneCycleLR(opt, max_lr=args.lr, total_steps=steps, pct_start=0.15)
    start = time.time()
    for epoch in range(args.epochs):
        order = rng.permutation(len(train_images))
        total = 0.0
        for s in range(0, len(order), args.batch):
            idx = order[s:s + args.batch]
            batch, boxes = augment(train_images[idx], [train_boxes[i] for i in idx], rng)
            heat, reg, mask, size_mask = targets(boxes, args.size_radius)
            out = net(torch.from_numpy(batch).permute(0, 3, 1, 2).contiguous())
            loss_heat = focal_loss(out[:, :1], heat)
            npos = mask.sum().clamp(min=1.0)
            loss_off = (F.l1_loss(out[:, 1:3], reg[:, :2], reduction="none") * mask).sum() / npos
            loss_size = (F.l1_loss(out[:, 3:5], reg[:, 2:4], reduction="none") * size_mask).sum() / size_mask.sum().clamp(min=1.0)
            loss = loss_heat + loss_off + loss_size
            opt.zero_grad()
            loss.backward()
            opt.step()
            sched.step()
            total += float(loss) * len(idx)
        msg = "epoch %d/%d loss %.4f (%.0f s)" % (epoch + 1, args.epochs, total / len(order), time.time() - start)
        if (epoch + 1) % 5 == 0 or epoch + 1 == args.epochs:
            m = evaluate(net, val_images, val_boxes)
            msg += "  val recall %.3f mean IoU %.3f false positives %.3f" % (
                m["recall"], m["mean_iou"], m["false_positive_rate"])
        print(msg, flush=True)

    net.eval()
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    torch.onnx.export(net, torch.zeros(1, 3, H_IN, W_IN), args.out, opset_version=11, input_names=["rgb"],
                      output_names=["maps"], do_constant_folding=True)
    import onnx
    model = onnx.load(args.out)
    onnx.checker.check_model(model)
    ops = sorted({n.op_type for n in model.graph.node})
    print("wrote %s (%d bytes), ops: %s" % (args.out, os.path.getsize(args.out), ", ".join(ops)), flush=True)
    allowed = {"Conv", "Relu", "Resize", "Concat", "BatchNormalization", "Constant", "MaxPool", "Identity"}
    if not set(ops) <= allowed:
        raise SystemExit("the graph uses ops OpenCV 4.6 dnn may reject: %s" % (set(ops) - allowed))
    # The same check with OpenCV's dnn, which the C++ side uses.
    cvnet = cv2.dnn.readNetFromONNX(args.out)
    x = val_images[:1].astype(np.float32) / 255.0
    cvnet.setInput(np.ascontiguousarray(x.transpose(0, 3, 1, 2)))
    with torch.no_grad():
        ref = net(torch.from_numpy(x).permute(0, 3, 1, 2)).numpy()
    diff = float(np.abs(cvnet.forward() - ref).max())
    print("OpenCV dnn vs torch max difference %.2e" % diff, flush=True)
    if diff > 1e-3:
        raise SystemExit("OpenCV dnn disagrees with torch")


if __name__ == "__main__":
    main()
