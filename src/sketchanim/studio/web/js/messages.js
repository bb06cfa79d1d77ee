// @ts-check
/**
 * Every message on the studio's websocket, both ways, as JSDoc types (nothing runs here).
 * Page to server: the pydantic models of sketchanim/studio/protocol.py (each may carry an
 * `id`, answered by an `ack` or an `error` with the same id); server to page: what the
 * server's session and hub send. tests/studio/test_protocol_typedefs.py checks that the
 * types and their fields are the protocol's; tsc checks that the page sends and reads only
 * these fields (tests/studio/test_page_types.py).
 *
 * One block per message, keyed by its `type`; `preview` and `transport` go both ways (a
 * page's is relayed to the other pages) and have one block each. After the messages: the
 * shapes they carry (a scene object, a track, ...).
 */

// -- page to server ---------------------------------------------------------------------------

/**
 * @typedef {object} Ping
 * @property {'ping'} type
 * @property {number | string | null} [id]
 */

/**
 * Ask for the whole state again (answered by a `state` message).
 * @typedef {object} StateRequest
 * @property {'state'} type
 * @property {number | string | null} [id]
 */

/**
 * An undoable scene edit: `path` takes `value` (merged into the last History entry when
 * its `merge` key is the same).
 * @typedef {object} SetValue
 * @property {'set'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {Value} value
 * @property {string | null} [label]
 * @property {string | null} [merge]
 */

/**
 * A live value while the performer drags (not in History); the server relays it to the
 * other pages.
 * @typedef {object} PreviewValue
 * @property {'preview'} type
 * @property {number | string | null} [id]
 * @property {string} key
 * @property {string} path
 * @property {Value} value
 */

/**
 * Add an object (undoable), at `position` if given (the page places it in front of its camera).
 * @typedef {object} ObjectAdd
 * @property {'object.add'} type
 * @property {number | string | null} [id]
 * @property {string} name
 * @property {ObjectKind} [kind]
 * @property {[number, number, number] | null} [position]
 */

/**
 * Copy the object `name` (its values and tracks) as `to` (undoable).
 * @typedef {object} ObjectDuplicate
 * @property {'object.duplicate'} type
 * @property {number | string | null} [id]
 * @property {string} name
 * @property {string} to
 */

/**
 * Move control points of one or more curves as one History step.
 * @typedef {object} CurvePoints
 * @property {'curve.points'} type
 * @property {number | string | null} [id]
 * @property {{path: string, index: number, value: number[]}[]} edits
 * @property {string | null} [label]
 */

/**
 * Set the value and / or the slope (per second) of a curve at `time` (a key or its handle
 * dragged): the least change of the control points active there, one History step.
 * @typedef {object} CurveKey
 * @property {'curve.key'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number} time
 * @property {number[] | null} [value]
 * @property {number[] | null} [slope]
 * @property {string | null} [label]
 */

/**
 * Insert knots at times `insert` and remove the interior knots `remove` (indices into the
 * curve's `knots`), one History step.
 * @typedef {object} CurveKnots
 * @property {'curve.knots'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number[]} [insert]
 * @property {number[]} [remove]
 */

/**
 * Key the discrete attribute `path` to `value` at transport time `time` (an event: a label
 * or null), one History step.
 * @typedef {object} TrackKey
 * @property {'track.key'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number} time
 * @property {boolean | string | null} [value]
 */

/**
 * Re-reduce tracks from their raw takes within `tol` (the attribute's units); `preview`:
 * only answered (`reduced` with the would-be curves), else one History step.
 * @typedef {object} TrackReduce
 * @property {'track.reduce'} type
 * @property {number | string | null} [id]
 * @property {string[]} paths
 * @property {number} tol
 * @property {boolean} [preview]
 */

/**
 * Ask for the samples a curve keeps within its tolerance (answered by `samples`).
 * @typedef {object} TrackSamples
 * @property {'track.samples'} type
 * @property {number | string | null} [id]
 * @property {string} path
 */

/** @typedef {'rename' | 'mute' | 'unmute' | 'solo' | 'delete' | 'move' | 'keep' | 'shift' | 'scale'} TakeOp */

/**
 * Change take `take` (its index in the track's takes) of the track at `path`: the track is
 * composed again from its takes (one History step).
 * @typedef {object} TakeEdit
 * @property {'take.edit'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number} take
 * @property {TakeOp} op
 * @property {string | null} [name]   for `rename`
 * @property {number | null} [to]     for `move`: the take's new index
 * @property {number | null} [by]     for `shift`: seconds later (earlier if negative)
 * @property {number | null} [factor] for `scale`: the time scale (> 0)
 * @property {number | null} [pivot]  for `scale`: the time that stays (null: the take's start)
 */

// -- the timeline: retiming and the clipboard -------------------------------------------------

/**
 * Retime tracks as a whole: time t goes to pivot + factor (t - pivot) + shift (one History step).
 * @typedef {object} TrackRetime
 * @property {'track.retime'} type
 * @property {number | string | null} [id]
 * @property {string[]} paths
 * @property {number} [factor]
 * @property {number} [pivot]
 * @property {number} [shift]
 */

/**
 * Delete the motion of tracks over (t0, t1): a curve bridged across (one History step).
 * @typedef {object} TrackCut
 * @property {'track.cut'} type
 * @property {number | string | null} [id]
 * @property {string[]} paths
 * @property {number} t0
 * @property {number} t1
 */

/**
 * Copy a track's motion over (t0, t1) (answered by `track.piece`, the page's clipboard).
 * @typedef {object} TrackCopy
 * @property {'track.copy'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number} t0
 * @property {number} t1
 */

/**
 * Put a copied piece on the track at `path` from time `at` (one History step).
 * @typedef {object} TrackPaste
 * @property {'track.paste'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number} at
 * @property {Track} piece
 * @property {number} length
 */

/**
 * The project's settings (the frame rate), kept by the project and sent to every page.
 * @typedef {object} SettingsChange
 * @property {'settings'} type
 * @property {number | string | null} [id]
 * @property {number} fps
 */

/**
 * @typedef {object} ObjectRemove
 * @property {'object.remove'} type
 * @property {number | string | null} [id]
 * @property {string} name
 */

/**
 * @typedef {object} ObjectRename
 * @property {'object.rename'} type
 * @property {number | string | null} [id]
 * @property {string} name
 * @property {string} to
 */

/**
 * Start a take of `paths` at transport time `time` (at `speed` transport seconds per real
 * second; a step of more than `gap` real seconds between samples is a stall), its samples
 * smoothed over `smoothing` seconds before they are reduced (0: not; the raw are kept).
 * @typedef {object} TakeBegin
 * @property {'take.begin'} type
 * @property {number | string | null} [id]
 * @property {string} take
 * @property {string[]} paths
 * @property {LayerMode} [mode]
 * @property {number} [blend]
 * @property {number} [time]
 * @property {number} [speed]
 * @property {Record<string, number>} [tol]
 * @property {string | null} [loop]
 * @property {number} [gap]
 * @property {number} [smoothing]
 */

/**
 * Samples of the running take: transport times and rows of its layout.
 * @typedef {object} TakeSamples
 * @property {'take.samples'} type
 * @property {number | string | null} [id]
 * @property {string} take
 * @property {number[]} t
 * @property {number[][]} values
 */

/**
 * @typedef {object} TakeEnd
 * @property {'take.end'} type
 * @property {number | string | null} [id]
 * @property {string} take
 * @property {string | null} [label]
 */

/**
 * @typedef {object} TakeCancel
 * @property {'take.cancel'} type
 * @property {number | string | null} [id]
 * @property {string} take
 */

/**
 * @typedef {object} Undo
 * @property {'undo'} type
 * @property {number | string | null} [id]
 */

/**
 * @typedef {object} Redo
 * @property {'redo'} type
 * @property {number | string | null} [id]
 */

/**
 * Write the scene (.glb) or the project (.json) into the project's folder.
 * @typedef {object} Export
 * @property {'export'} type
 * @property {number | string | null} [id]
 * @property {string} file
 * @property {boolean} [overwrite]  replace a file of that name (never the project's own)
 */

/**
 * The tolerance takes of `path` are recorded within, kept by the project (not a History
 * step): `amount` input steps (`unit` 'px': pixels for a pointer) or the attribute's units
 * ('units'); `amount` null: back to what the input resolves (resolution.js).
 * @typedef {object} ToleranceSet
 * @property {'tolerance.set'} type
 * @property {number | string | null} [id]
 * @property {string} path
 * @property {number | null} [amount]
 * @property {'px' | 'units'} [unit]
 */

// -- both ways ----------------------------------------------------------------------------------

/**
 * The transport and the record settings: a page's (kept for a reload), relayed to the other
 * pages. `count_in` seconds of pre-roll, `capture_speed` transport seconds per real second
 * while recording, the layer `mode`, `loop_record` (each pass of the loop a take), the
 * `smoothing` of the next takes (seconds, 0: off).
 * @typedef {object} TransportState
 * @property {'transport'} type
 * @property {number | string | null} [id]
 * @property {number} time
 * @property {boolean} playing
 * @property {number} speed
 * @property {[number, number] | null} loop
 * @property {number} count_in
 * @property {number} capture_speed
 * @property {LayerMode} mode
 * @property {boolean} loop_record
 * @property {number} smoothing
 */

// -- server to page -----------------------------------------------------------------------------

/**
 * Everything a page shows: the scene, the tracks, the history, the transport, the take in
 * progress (sent on connecting, and when objects come or go).
 * @typedef {object} StateSnapshot
 * @property {'state'} type
 * @property {boolean} ready
 * @property {string} project
 * @property {SceneObject[]} objects
 * @property {Track[]} tracks
 * @property {[number, number]} span
 * @property {HistoryLabels} history
 * @property {TransportFields} transport
 * @property {TakeInProgress | null} take
 * @property {Record<string, ToleranceSetting>} tolerances  the animator's take tolerances, by path
 * @property {Saved} [saved]  whether everything is on disk
 * @property {boolean} [read_only]  the project cannot be written: it plays and exports, edits are refused
 * @property {SettingsInfo} [settings]  the project's settings (the frame rate)
 * @property {SoundInfo[]} [sounds]  the project's sounds
 */

/**
 * The project's settings changed (also in every `state`).
 * @typedef {object} SettingsInfo
 * @property {'settings'} type
 * @property {number} fps
 */

/**
 * The answer to `track.reduce`: each track's control points and largest error; for a
 * preview, the would-be curves too.
 * @typedef {object} Reduced
 * @property {'reduced'} type
 * @property {boolean} preview
 * @property {{path: string, tol: number, n: number, error: number}[]} results
 * @property {CurveTrack[]} curves
 */

/**
 * The answer to `track.samples`: the samples the curve keeps within `tol`.
 * @typedef {object} Samples
 * @property {'samples'} type
 * @property {string} path
 * @property {number} tol
 * @property {number[]} times
 * @property {number[][]} values
 */

/**
 * A copied range of the track at `path` (starting at 0, `length` seconds): the page's clipboard.
 * @typedef {object} TrackPieceInfo
 * @property {'track.piece'} type
 * @property {string} path
 * @property {Track} piece
 * @property {number} length
 */

/**
 * Whether everything the pages were told is on disk: `ok`, else `error` says why the last
 * save failed and `since` when (epoch seconds) saves began to fail. The
 * server keeps what is not saved and saves it at the next chance.
 * @typedef {object} Saved
 * @property {'saved'} type
 * @property {boolean} ok
 * @property {string | null} error
 * @property {number | null} since
 */

/**
 * The animator's take tolerances changed: all of them, by path.
 * @typedef {object} Tolerances
 * @property {'tolerances'} type
 * @property {Record<string, ToleranceSetting>} tolerances
 */

/**
 * The server's compiled kernels are warm: takes can be recorded.
 * @typedef {object} Ready
 * @property {'ready'} type
 */

/**
 * Scene values that changed, by path.
 * @typedef {object} Values
 * @property {'values'} type
 * @property {Record<string, Value>} values
 */

/**
 * Tracks that changed or went, and the tracks' span after.
 * @typedef {object} Tracks
 * @property {'tracks'} type
 * @property {Track[]} changed
 * @property {string[]} removed
 * @property {[number, number]} span
 */

/**
 * The History's labels (oldest first).
 * @typedef {object} History
 * @property {'history'} type
 * @property {string[]} undo
 * @property {string[]} redo
 * @property {boolean} can_undo
 * @property {boolean} can_redo
 */

/**
 * The take this page began is being recorded: the layout of its rows.
 * @typedef {object} TakeStarted
 * @property {'take.started'} type
 * @property {string} take
 * @property {[string, number, number][]} layout  path, first and last + 1 column of each attribute
 * @property {number} width
 */

/**
 * Another page began a take (it alone records until its `take.ended`).
 * @typedef {object} TakeRunning
 * @property {'take.running'} type
 * @property {string} take
 * @property {string[]} paths
 * @property {LayerMode} mode
 * @property {number} time
 * @property {[string, number, number][]} layout
 */

/**
 * A piece of the take's curve, reduced as the server finished a window.
 * @typedef {object} TakePiece
 * @property {'take.piece'} type
 * @property {string} take
 * @property {string} path
 * @property {number} order
 * @property {boolean} rotation
 * @property {number[]} knots
 * @property {number[][]} coef
 */

/**
 * A take ended: its History label (null: nothing made, or cancelled), the paths it made,
 * the server's milliseconds from the end's message to the final curve, its stalls, and the
 * seconds its samples were smoothed over (0: not smoothed).
 * @typedef {object} TakeEnded
 * @property {'take.ended'} type
 * @property {string} take
 * @property {string | null} label
 * @property {string[]} paths
 * @property {number} ms
 * @property {[number, number][]} gaps
 * @property {number} smoothing
 * @property {'end' | 'cancel' | 'gone' | 'silent' | 'shutdown'} [reason]  why it ended
 */

/**
 * @typedef {object} Pong
 * @property {'pong'} type
 * @property {number | string | null} id
 * @property {number} server_time
 */

/**
 * A message with an id was done.
 * @typedef {object} Ack
 * @property {'ack'} type
 * @property {number | string | null} id
 * @property {string | null} ref
 */

/**
 * A message was refused: `ref` is its type, `code` one of "rate", "too_large",
 * "bad_message", "busy", "refused", "read_only", "exists", "failed".
 * @typedef {object} ErrorReply
 * @property {'error'} type
 * @property {number | string | null} id
 * @property {string | null} ref
 * @property {string} code
 * @property {string} message
 */

/**
 * A file was exported into the project's folder.
 * @typedef {object} Exported
 * @property {'exported'} type
 * @property {string} file
 */

/**
 * Something the animator should know that no request asked for (a recorder's warning: a
 * reducer process died, the journal failed), also in the server's log.
 * @typedef {object} Notice
 * @property {'notice'} type
 * @property {NoticeLevel} level
 * @property {string} text
 * @property {string} source
 */

// -- sounds (studio/sounds.py, studio/beats.py; the page's sound.js) -------------------------

/**
 * Start the sound `name` at `offset` seconds on the timeline (a project setting, not History).
 * @typedef {object} SoundSet
 * @property {'sound.set'} type
 * @property {number | string | null} [id]
 * @property {string} name
 * @property {number} offset
 */

/**
 * Drop the sound `name` from the project (its file stays in the sounds folder).
 * @typedef {object} SoundRemove
 * @property {'sound.remove'} type
 * @property {number | string | null} [id]
 * @property {string} name
 */

/**
 * Bake the onsets of sound `name` into an event track at `path` (default `beats.cue`, a
 * cue object made for it): one History step.
 * @typedef {object} SoundBeats
 * @property {'sound.beats'} type
 * @property {number | string | null} [id]
 * @property {string} name
 * @property {string | null} [path]
 */

/**
 * The project's sounds changed: all of them.
 * @typedef {object} SoundsInfo
 * @property {'sounds'} type
 * @property {SoundInfo[]} sounds
 */

/**
 * The answer to `sound.beats`: how many beats went on `path`.
 * @typedef {object} BeatsBaked
 * @property {'beats'} type
 * @property {string} name
 * @property {string} path
 * @property {number} count
 */

/**
 * A sound of the project: its file's path (relative to the project's folder), SHA-256, duration
 * and start on the timeline (s), whether its file is as imported, and the URL serving it.
 * @typedef {{name: string, path: string, sha256: string, duration: number, offset: number,
 *   status: 'ok' | 'missing' | 'changed', url: string}} SoundInfo
 */

// -- the unions -----------------------------------------------------------------------------

/**
 * What the page sends.
 * @typedef {Ping | StateRequest | SetValue | PreviewValue | ObjectAdd | ObjectDuplicate | ObjectRemove | ObjectRename
 *   | TakeBegin | TakeSamples | TakeEnd | TakeCancel | Undo | Redo | TransportState | Export | ToleranceSet
 *   | CurvePoints | CurveKey | CurveKnots | TrackKey | TrackReduce | TrackSamples | TakeEdit | SettingsChange
 *   | TrackRetime | TrackCut | TrackCopy | TrackPaste | SoundSet | SoundRemove | SoundBeats} PageMessage
 */

/**
 * What the server sends.
 * @typedef {StateSnapshot | Ready | Values | Tracks | History | PreviewValue | TransportState | TakeStarted
 *   | TakePiece | TakeEnded | Pong | Ack | ErrorReply | Exported | Notice | Tolerances | TakeRunning
 *   | Saved | SettingsInfo | Reduced | Samples | TrackPieceInfo | SoundsInfo | BeatsBaked} ServerMessage
 */

/**
 * The server's message of one type.
 * @template {ServerMessage['type']} T
 * @typedef {Extract<ServerMessage, {type: T}>} ServerMessageOf
 */

// -- what the messages carry ----------------------------------------------------------------

/**
 * An attribute's value as JSON: a list of numbers (orientations scalar-last x, y, z, w; a
 * field of view in degrees), or a bool / string for discrete attributes.
 * @typedef {number[] | boolean | string | null} Value
 */

/** @typedef {'object' | 'light' | 'camera' | 'chain' | 'walker'} ObjectKind */
/** @typedef {import('./resolution.js').ToleranceSetting} ToleranceSetting */
/** @typedef {'replace' | 'additive'} LayerMode */
/** @typedef {'info' | 'warning' | 'error'} NoticeLevel */

/**
 * An attribute's type.
 * @typedef {{name: string, dim: number, tol: number, unit: string, default: any[], choices: string[], continuous: boolean}} AttrType
 */

/**
 * A scene object and its attributes.
 * A cue has no place in space: it holds an event track (a sound's beats).
 * @typedef {{name: string, kind: ObjectKind | 'cue', attributes: {name: string, value: any, type: AttrType}[]}} SceneObject
 */

/**
 * One take of a curve: its span, mode, samples, smoothing (s), name ('' none given), whether
 * it is muted, the loop recording it is part of (null: none) and its pass (0, 1, ...).
 * @typedef {{start: number, end: number, mode: string, n: number, smoothing: number, name?: string, muted?: boolean,
 *   loop?: string | null, loop_pass?: number}} TakeSpanInfo
 */

/**
 * A continuous track (a B-spline), as the page evaluates it, with the takes it was made of;
 * `edited`: its points or keys were moved by hand since it was composed from its takes.
 * @typedef {{path: string, kind: 'curve', dim: number, order: number, rotation: boolean, tol: number, knots: number[],
 *   coef: number[][], start: number, end: number, takes: TakeSpanInfo[], bounds?: (number|null)[] | null,
 *   edited?: boolean}} CurveTrack
 */

/**
 * A discrete track: values holding from their time on.
 * @typedef {{path: string, kind: 'steps', times: number[], values: any[]}} StepsTrack
 */

/** @typedef {CurveTrack | StepsTrack} Track */

/** @typedef {Omit<History, 'type'>} HistoryLabels */

/** @typedef {Omit<TransportState, 'type' | 'id'>} TransportFields */

/**
 * @typedef {{take: string, paths: string[], mode: LayerMode, time: number, layout: [string, number, number][]}} TakeInProgress
 */

export {};
