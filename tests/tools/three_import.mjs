// Loads crackle .glb files with three.js's GLTFLoader, as a web engine would (geometry only:
// Node.js has no image decoder), and prints, in three.js's +Y-up frame, the size of the scene's
// bounding box and the triangle area facing +Y and -Y (a test checks mud lies flat, face up,
// and the bark trunk stands along Y).
//   node tests/tools/three_import.mjs .tools/node_modules file.glb ...
// scripts/setup installs three.js (pinned) into .tools/.
import fs from 'fs';
import path from 'path';
import { pathToFileURL } from 'url';
const modules = process.argv[2];
const THREE = await import(pathToFileURL(path.join(modules, 'three', 'build', 'three.module.js')));
const { GLTFLoader } = await import(
    pathToFileURL(path.join(modules, 'three', 'examples', 'jsm', 'loaders', 'GLTFLoader.js')));
globalThis.self = globalThis;
for (const file of process.argv.slice(3)) {
  const buf = fs.readFileSync(file);
  const ab = buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength);
  const loader = new GLTFLoader();
  // Skip textures: node has no createImageBitmap.
  loader.register(parser => ({ name: 'skip', loadTexture: () => Promise.resolve(new THREE.Texture()) }));
  await new Promise((resolve) => loader.parse(ab, '', (gltf) => {
    const box = new THREE.Box3().setFromObject(gltf.scene);
    let up = 0, down = 0, meshes = 0;
    gltf.scene.traverse(o => {
      if (!o.isMesh) return; meshes++;
      const g = o.geometry.toNonIndexed(); const p = g.attributes.position;
      const a = new THREE.Vector3(), b = new THREE.Vector3(), c = new THREE.Vector3();
      for (let i = 0; i < p.count; i += 3) {
        a.fromBufferAttribute(p, i); b.fromBufferAttribute(p, i + 1); c.fromBufferAttribute(p, i + 2);
        const n = new THREE.Vector3().crossVectors(b.clone().sub(a), c.clone().sub(a));
        const area = n.length() / 2; n.normalize();
        if (n.y > 0.9) up += area; if (n.y < -0.9) down += area;
      }
    });
    const s = box.getSize(new THREE.Vector3());
    console.log(`${file}: meshes ${meshes}, size x ${s.x.toFixed(3)} y ${s.y.toFixed(3)} z ${s.z.toFixed(3)} m; area facing +Y ${up.toFixed(4)} m2, -Y ${down.toFixed(4)} m2`);
    resolve();
  }, (e) => { console.log(file + ': ERROR ' + e); resolve(); }));
}
