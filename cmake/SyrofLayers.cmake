# The layering of SyROF's modules, lowest first: the one place it is written.
#
# A module may include the headers (and link the targets) of modules in LOWER
# groups, and its own; never those of its own group's siblings or of a higher
# group. cmake/CheckLayers.cmake checks every #include of core/, queries/,
# lab/, cli/, firmware/, sim_dds/, app_host/ and grader/ against this list (ctest label
# `architecture`), and syrof_add_library (cmake/SyrofHelpers.cmake) refuses a
# link dependency on a module that is not below at configure time.
#
# Headers map to modules by their path under include/: syrof/base/... is
# core/base, syrof/app.h and syrof/app/... core/app, syrof/os/... (with its
# sim/ and posix/ ports) core/os, syrof/queries/... queries,
# syrof/lab/<m>/... lab/<m>, syrof/board/... firmware. Sources map by their
# folder: core/<m>/..., lab/<m>/..., queries/..., cli/..., and so on.
#
# Why the order is what it is:
# - core/registry (topic ids, task priorities), core/wire (the beacon) and
#   queries (exact geometry) need only core/base.
# - core/estimation is the filter's math and needs only core/base and Eigen,
#   so it sits beside core/wire: the check then refuses it any os, pubsub or
#   registry header. Its task shell, core/estimation/tasks (the state and
#   Kalman tasks on the broker), is a module of its own above os and pubsub,
#   as the Crazyflie separates kalman_core from estimator_kalman.
# - core/motion includes syrof/app.h (syrof_car_command), so it sits above
#   core/app and below core/runtime, which wires everything of core.
# - lab/base (the error value) is what every lab module shares.
# - firmware (the cross-compiled robot: NvicPort and the kernel, the
#   drivers, the robot image, the boards) runs core on a board and needs
#   nothing of lab: it sits beside lab/base, so the check refuses it every
#   lab header. Its host tool, the emulated swarm's host (firmware/swarm,
#   syrof-firmware-swarm: qemu processes, the beacon channel, the world
#   loop), is a module of its own above lab, the process module and the
#   firmware's headers it reads (the radio link, the boot words). Its other
#   host tool, firmware/config (syrof-firmware-config: a robot's
#   configuration block from a scenario, written into a copy of the image),
#   reads scenarios and the firmware's block format and runs nothing: it
#   sits just above lab/scenario, beside lab/metrics and lab/replay, so the
#   check refuses it the engine, the process module and the app host.
# - lab/message (a message format: what a payload's bytes mean) is pure and
#   needs only lab/base: the scenario reads it from YAML, the replay stores
#   it, the view and the grader decode and check payloads with it.
# - In lab, the sensors and the apps use only core (and queries); the world
#   uses the sensors' TrueState; the scenario holds the world's specs
#   (arena, kinds, channel), the sensors' noise models and checks app names
#   against lab/apps' catalog; lab/goals (the declarative goal checks:
#   geometry on true poses, with the queries) sits beside the apps so the
#   scenario can hold its checks; metrics and replay are fed by the engine
#   and know no scenario; lab/sim runs all of them. lab/view (the viewer's
#   page) reads replays only, beside lab/sim; the grader embeds its page.
# - lab/search (search tests) runs lab/sim again and again, so it sits
#   above it. lab/live (the live page's HTTP server) feeds lab/view's page
#   from a run's rounds, so it sits beside it, above lab/view.
# - sim_dds and firmware/swarm run core/runtime in other processes (DDS
#   robots, qemu instances) around lab/sim's world loop (WorldPlayer,
#   RoundRecorder); they are siblings: neither includes the other. The
#   grader sits above everything that runs a robot; cli is the top.
# - bridge (the base station, syrof-bridge) reads the firmware's radio link
#   framing and publishes on sim_dds's beacon topic, so it sits above both
#   (its own group: it runs no robot, nothing above needs it).
# - app_host/process (Spawn, the sandbox's steps, Fd, Landlock) needs only
#   the C library: it sits below every module that starts a process (the
#   app host, sim_dds, the firmware swarm host, the grader). Host only.
#   Nothing else includes <spawn.h> (SYROF_EXCLUSIVE_HEADERS below).
# - app_host (a student's library in a sandboxed process per robot) sits
#   below sim_dds and the grader, which both run student libraries through
#   it (the lab's `syrof run` too). Its hosts need only core/app and
#   queries; its app supply (AppsFor: a run's apps from its scenario, the
#   one setup every runtime uses) reads the scenario and makes the built-in
#   apps, so it sits above lab. The value it fills (lab/apps' AppSupply) is
#   in lab, where the engine's options hold it.
# - grader/assignment (assignment files and the rubric's scoring) reads
#   scenarios and metrics; the grade command's runner (grader) sits on it.
# - grader/report (results.json, JUnit, the HTML report with lab/view's
#   pages, the Gradescope bundle) only reads a SubmissionResult
#   (grader/assignment's result.h), so it sits between grader/assignment
#   and the runner, which calls it.
set(SYROF_LAYERS
  "core/base"
  "core/registry core/wire queries core/estimation"
  "core/os"
  "core/pubsub"
  "core/sync core/estimation/tasks"
  "core/app"
  "core/motion"
  "core/runtime"
  "lab/base firmware"
  "lab/sensors lab/apps lab/goals lab/message"
  "lab/world"
  "lab/scenario"
  "lab/metrics lab/replay firmware/config"
  "lab/sim lab/view"
  "lab/search lab/live"
  "app_host/process"
  "app_host"
  "sim_dds firmware/swarm"
  "bridge"
  "grader/assignment"
  "grader/report"
  "grader"
  "cli")

# Third-party (and board) headers only one module may include, as
# "<include path prefix>=<module>": CGAL only in queries (its exact kernels
# are the queries' business), Cyclone DDS only in sim_dds, the boards'
# headers only in firmware, cpp-httplib only in lab/live (the one HTTP
# server), posix_spawn's <spawn.h> only in app_host/process (the one place a
# child process is started; fork and exec come with <unistd.h>, which every
# module may include, so only a review finds those).
set(SYROF_EXCLUSIVE_HEADERS
  "CGAL/=queries"
  "dds/=sim_dds"
  "ddscxx/=sim_dds"
  "org/eclipse/cyclonedds/=sim_dds"
  "syrof/board/=firmware"
  "httplib.h=lab/live"
  "spawn.h=app_host/process")

# Modules that live in a folder of another module: their files (and the
# headers under their own include/) belong to them, not to the outer one.
set(SYROF_NESTED_MODULES "core/estimation/tasks" "app_host/process" "firmware/swarm" "firmware/config"
                         "grader/assignment" "grader/report")

# The top-level folders whose sources the check walks.
set(SYROF_LAYERED_FOLDERS core queries lab cli firmware sim_dds app_host grader bridge)
