// `gloc forecast` on comet's real deployment, its outputs checked by tools that did not
// write them: the GeoJSON against the GeoJSON schema (the npm package geojson-schema,
// pinned, the schemas of geojson.org) with ajv; the KML parsed by Python's ElementTree
// and held to the KML 2.2 schema's required structure (a kml root in the KML namespace,
// a Document, Placemarks with one geometry each, coordinates as lon,lat,alt tuples,
// polygon rings closed with at least four positions).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import Ajv from 'ajv';

const GLOC_BIN = process.env.GLOC_BIN;
if (!GLOC_BIN) throw new Error('GLOC_BIN must name the gloc binary (tests/e2e/run sets it)');
const require = createRequire(import.meta.url);
const DATA = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'data');
const folder = mkdtempSync(join(tmpdir(), 'gloc-forecast-'));
const geojsonPath = join(folder, 'comet.geojson');
const kmlPath = join(folder, 'comet.kml');
const stdout = execFileSync(GLOC_BIN, [
  'forecast',
  join(DATA, 'comet/from-glider/comet-2019-222-02-152.sbd'),
  join(DATA, 'comet/from-glider/comet-2019-222-02-153.sbd'),
  join(DATA, 'comet/from-glider/comet-2019-222-02-154.dbd'),
  '--sensor-cache', join(DATA, 'cac'),
  '--mission', join(DATA, 'comet/missions/nsb3.mi'),
  '--hours', '12', '--members', '40', '--seed', '5',
  '-o', geojsonPath, '-o', kmlPath,
], { encoding: 'utf8' });

test('the forecast prints its surfacings', () => {
  assert.match(stdout, /predicted surfacings/);
  assert.match(stdout, /ensemble 40 members, seed 5/);
});

test('the GeoJSON is valid against the GeoJSON schema', () => {
  const schema = require('geojson-schema/FeatureCollection.json');
  const ajv = new Ajv({ allErrors: true, strict: false });
  const validate = ajv.compile(schema);
  const document = JSON.parse(readFileSync(geojsonPath, 'utf8'));
  assert.ok(validate(document), JSON.stringify(validate.errors, null, 1));
  const kinds = document.features.map((f) => `${f.properties.kind}:${f.geometry.type}`);
  assert.ok(kinds.includes('track:LineString'));
  assert.equal(kinds.filter((k) => k === 'region:Polygon').length, 12, kinds.join(' '));
  assert.ok(kinds.filter((k) => k === 'surfacing:Point').length >= 3, kinds.join(' '));
});

test('the KML has the structure the KML 2.2 schema requires', () => {
  const check = String.raw`
import sys
import xml.etree.ElementTree as ET
K = "{http://www.opengis.net/kml/2.2}"
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == K + "kml", root.tag
documents = root.findall(K + "Document")
assert len(documents) == 1
placemarks = list(documents[0].iter(K + "Placemark"))
assert placemarks, "no Placemark"
geometries = {"Point", "LineString", "LinearRing", "Polygon", "MultiGeometry"}
counts = {}
for placemark in placemarks:
    found = [child for child in placemark if child.tag[len(K):] in geometries]
    assert len(found) == 1, "a Placemark has one geometry"
    kind = found[0].tag[len(K):]
    counts[kind] = counts.get(kind, 0) + 1
    for coordinates in found[0].iter(K + "coordinates"):
        tuples = coordinates.text.split()
        for item in tuples:
            lon, lat, alt = (float(v) for v in item.split(","))
            assert -180 <= lon <= 180 and -90 <= lat <= 90
        if kind == "Polygon":
            assert len(tuples) >= 4 and tuples[0] == tuples[-1], "a closed ring"
for polygon in root.iter(K + "Polygon"):
    assert polygon.find(K + "outerBoundaryIs/" + K + "LinearRing/" + K + "coordinates") is not None
print(" ".join(f"{k}={v}" for k, v in sorted(counts.items())))
`;
  const python = process.env.PYTHON || 'python3';
  const out = execFileSync(python, ['-c', check, kmlPath], { encoding: 'utf8' });
  assert.match(out, /LineString=1/);
  assert.match(out, /Polygon=\d+/);
});
