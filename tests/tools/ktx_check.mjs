// Independent KTX2 check: reads FILE with ktx-parse (not our reader) and compares what it finds
// with EXPECTED.json, written by tests/judges/ktx_parse_check_test.cpp. Exit 0 when everything
// matches; otherwise prints each mismatch and exits 1.
import { read } from 'ktx-parse';
import { readFileSync } from 'node:fs';

const [file, expectedPath] = process.argv.slice(2);
const want = JSON.parse(readFileSync(expectedPath, 'utf8'));
const ktx = read(new Uint8Array(readFileSync(file)));
const errors = [];
const eq = (what, got, exp) => {
  if (got !== exp) errors.push(`${what}: got ${got}, expected ${exp}`);
};

eq('vkFormat', ktx.vkFormat, want.vkFormat);
eq('typeSize', ktx.typeSize, want.typeSize);
eq('pixelWidth', ktx.pixelWidth, want.width);
eq('pixelHeight', ktx.pixelHeight, want.height);
eq('pixelDepth', ktx.pixelDepth, 0);
eq('layerCount', ktx.layerCount, want.layerCount ?? 0);
eq('faceCount', ktx.faceCount, 1);
eq('levelCount', ktx.levelCount, want.levels.length);
eq('supercompressionScheme', ktx.supercompressionScheme, want.supercompression);
eq('levels.length', ktx.levels.length, want.levels.length);
want.levels.forEach((lv, i) => {
  const got = ktx.levels[i];
  if (!got) return;
  eq(`level ${i} uncompressedByteLength`, got.uncompressedByteLength, lv.bytes);
  if (want.supercompression === 0) {
    eq(`level ${i} byteLength`, got.levelData.byteLength, lv.bytes);
    const raw = readFileSync(lv.raw);
    if (Buffer.compare(Buffer.from(got.levelData), raw) !== 0) errors.push(`level ${i} data differs`);
  }
});
const dfd = ktx.dataFormatDescriptor[0];
eq('dfd.vendorId', dfd.vendorId, 0);
eq('dfd.descriptorType', dfd.descriptorType, 0);
eq('dfd.versionNumber', dfd.versionNumber, 2);
eq('dfd.colorModel', dfd.colorModel, want.dfd.colorModel);
eq('dfd.colorPrimaries', dfd.colorPrimaries, 1);
eq('dfd.transferFunction', dfd.transferFunction, 1);
want.dfd.texelBlockDimension.forEach((v, i) => eq(`dfd.texelBlockDimension[${i}]`, dfd.texelBlockDimension[i], v));
eq('dfd.bytesPlane[0]', dfd.bytesPlane[0], want.dfd.bytesPlane0);
eq('dfd.samples.length', dfd.samples.length, want.dfd.samples.length);
want.dfd.samples.forEach((s, i) => {
  const g = dfd.samples[i];
  if (!g) return;
  eq(`sample ${i} bitOffset`, g.bitOffset, s.bitOffset);
  eq(`sample ${i} bitLength`, g.bitLength, s.bitLength);
  eq(`sample ${i} channelType`, g.channelType, s.channelType);
  // ktx-parse reads limits as signed when the SIGNED flag is set: compare as uint32.
  eq(`sample ${i} sampleLower`, g.sampleLower >>> 0, s.lower);
  eq(`sample ${i} sampleUpper`, g.sampleUpper >>> 0, s.upper);
});
for (const [k, v] of Object.entries(want.keyValue)) {
  let got = ktx.keyValue[k];
  if (got instanceof Uint8Array) got = Buffer.from(got).toString('utf8').replace(/\0$/, '');
  eq(`keyValue[${k}]`, got, v);
}
if (errors.length) {
  console.error(`${file}:\n  ` + errors.join('\n  '));
  process.exit(1);
}
