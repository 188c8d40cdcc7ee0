# An output never overwrites an input or the results store, and a full disk is an
# error: each command below must exit 1 with its message and leave its input as
# it was. CLI, OUT (a scratch folder), REC (a recording), MESH (a mesh), SCENE.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

function(expect_refused what expect)
  string(REPLACE "|" ";" args "${ARGN}")
  execute_process(COMMAND ${CLI} ${args} RESULT_VARIABLE status OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(status EQUAL 0)
    message(FATAL_ERROR "${what}: exit status 0, expected a refusal; output:\n${out}${err}")
  endif()
  if(NOT "${out}${err}" MATCHES "${expect}")
    message(FATAL_ERROR "${what}: output does not match '${expect}':\n${out}${err}")
  endif()
  message(STATUS "ok: ${what}")
endfunction()

function(expect_size file size what)
  file(SIZE ${file} now)
  if(NOT now EQUAL size)
    message(FATAL_ERROR "${what}: ${file} is ${now} bytes, was ${size}")
  endif()
endfunction()

# A recording exported onto itself, and through a hard link to it.
configure_file(${REC} ${OUT}/in.rec COPYONLY)
file(SIZE ${OUT}/in.rec rec_size)
expect_refused("recording export onto its input" "will not write .*in.rec: it is the recording being exported"
  recording|export|${OUT}/in.rec|--csv|-o|${OUT}/in.rec)
file(CREATE_LINK ${OUT}/in.rec ${OUT}/hard.rec)
expect_refused("recording export onto a hard link of its input" "it is the recording being exported"
  recording|export|${OUT}/in.rec|--csv|-o|${OUT}/hard.rec)
file(CREATE_LINK ${OUT}/in.rec ${OUT}/soft.rec SYMBOLIC)
expect_refused("recording export onto a symlink to its input" "it is the recording being exported"
  recording|export|${OUT}/in.rec|--csv|-o|${OUT}/soft.rec)
expect_size(${OUT}/in.rec ${rec_size} "the recording")

# A full disk: an error, not a 0-byte file and exit 0.
expect_refused("recording export to a full disk" "could not write /dev/full"
  recording|export|${OUT}/in.rec|--csv|-o|/dev/full)
expect_refused("mesh convert to a device" "/dev/full.*not a regular file"
  mesh|convert|${MESH}|/dev/full)

# A mesh converted onto itself.
get_filename_component(ext ${MESH} EXT)
configure_file(${MESH} ${OUT}/in${ext} COPYONLY)
file(SIZE ${OUT}/in${ext} mesh_size)
expect_refused("mesh convert onto its input" "it is the mesh being converted"
  mesh|convert|${OUT}/in${ext}|${OUT}/in${ext})
expect_size(${OUT}/in${ext} ${mesh_size} "the mesh")

# A session recorded onto its scene.
configure_file(${SCENE} ${OUT}/scene.yaml COPYONLY)
file(SIZE ${OUT}/scene.yaml scene_size)
expect_refused("run --record onto the scene" "it is the scene being run"
  run|--scene|${OUT}/scene.yaml|--device|scripted:poke|--seconds|0.1|--offline|--record|${OUT}/scene.yaml)
expect_size(${OUT}/scene.yaml ${scene_size} "the scene")

# The results database exported onto itself: refused before it is opened.
execute_process(COMMAND ${CLI} results list --results ${OUT}/results RESULT_VARIABLE s1
                OUTPUT_QUIET ERROR_QUIET)
file(SIZE ${OUT}/results/results.db db_size)
expect_refused("results export onto the database" "it is the results database"
  results|export|--results|${OUT}/results|-o|${OUT}/results/results.db)
expect_size(${OUT}/results/results.db ${db_size} "the results database")
execute_process(COMMAND ${CLI} results list --results ${OUT}/results RESULT_VARIABLE s2
                OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT s2 EQUAL 0)
  message(FATAL_ERROR "results list after the refused export: status ${s2}\n${out}${err}")
endif()
message(STATUS "ok: the database is intact")

# A lesson's report folder that already holds another attempt's report, or is a
# file: refused before the lesson runs.
file(MAKE_DIRECTORY ${OUT}/kept)
file(WRITE ${OUT}/kept/report.json "{}")
expect_refused("lesson run -o onto another attempt's folder" "already holds the report of another attempt"
  lesson|run|${LESSON}|--results|${OUT}/results|-o|${OUT}/kept)
file(WRITE ${OUT}/afile "x")
expect_refused("lesson run -o onto a file" "is a file, not a folder"
  lesson|run|${LESSON}|--results|${OUT}/results|-o|${OUT}/afile)

# A FIFO, a device or a folder given as an input is refused at once (it would
# block the command, or never end).
execute_process(COMMAND mkfifo ${OUT}/fifo RESULT_VARIABLE made)
if(made EQUAL 0)
  expect_refused("scene validate on a FIFO" "fifo.*is not a regular file"
    scene|validate|${OUT}/fifo)
  expect_refused("lesson validate on a FIFO" "fifo.*is not a regular file"
    lesson|validate|${OUT}/fifo)
  expect_refused("recording export of a FIFO" "fifo.*is not a regular file"
    recording|export|${OUT}/fifo|--csv)
  execute_process(COMMAND mkfifo ${OUT}/fifo.csv)
  expect_refused("a trajectory CSV that is a FIFO" "fifo.csv.*is not a regular file"
    run|--scene|${SCENE}|--device|scripted:${OUT}/fifo.csv|--seconds|0.1|--offline)
endif()
expect_refused("recording export of /dev/zero" "/dev/zero.*is not a regular file"
  recording|export|/dev/zero|--csv)
expect_refused("scene validate on a folder" "is a folder, not a file"
  scene|validate|${OUT})

# A scene exported: two objects whose file names would collide are refused
# before anything is written, and so is a mesh written over one the scene reads.
file(MAKE_DIRECTORY ${OUT}/exp)
file(WRITE ${OUT}/exp/collide.yaml
  "objects:\n  - name: a b\n    box: [2, 2, 2]\n    tissue: bone\n"
  "  - name: a-b\n    box: [3, 3, 3]\n    at: [10, 0, 0]\n    tissue: bone\n")
expect_refused("scene export of two objects named alike"
  "objects 'a b' and 'a-b' would both be written to a_b.stl"
  scene|export|${OUT}/exp/collide.yaml|-o|${OUT}/exp/out)
if(EXISTS ${OUT}/exp/out/a_b.stl)
  message(FATAL_ERROR "scene export wrote a_b.stl although it refused")
endif()
execute_process(COMMAND ${CLI} mesh convert ${MESH} ${OUT}/exp/part.stl
  RESULT_VARIABLE made)
file(SIZE ${OUT}/exp/part.stl part_size)
file(WRITE ${OUT}/exp/reads.yaml "objects:\n  - mesh: part.stl\n    tissue: bone\n")
expect_refused("scene export over a mesh the scene reads"
  "part.stl.*it is a mesh the scene reads"
  scene|export|${OUT}/exp/reads.yaml|-o|${OUT}/exp)
expect_size(${OUT}/exp/part.stl ${part_size} "the scene's mesh")

# A results folder that cannot be made (a read-only file system): said so, with
# what to do, and no SQLite text.
expect_refused("results list where no database can be made"
  "cannot be opened or made there.*SULCUS_RESULTS_DIR"
  results|list|--results|/proc/sulcus-results)
