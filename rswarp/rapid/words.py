"""Every RAPID word (the reference manual's, in ``words.tsv``, and the options' programs use) with
how rswarp handles it: the table the interpreter asks, printed for docs/program.md by ``python -m
rswarp.rapid.words``."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from importlib import resources

HANDLINGS = ("modelled", "no-op", "live", "unmodelled", "state")
MEANINGS = {
    "modelled": "rswarp computes it: the motion, the data, the value",
    "no-op": "no effect on the motion: run as nothing, silently (a data type: kept and passed on, never computed with)",
    "live": "its value exists only on the running cell (a socket, a file, the operator, a sensor): rswarp has none",
    "unmodelled": "could change the motion, or gives a value rswarp does not compute: not modelled, with a warning",
    "state": "the controller's state, a fixed answer offline (`STATE_VALUES`)",
}
SIGNAL_TYPES = frozenset({"signalai", "signalao", "signaldi", "signaldo", "signalgi", "signalgo", "signalxx"})
# What the controller's configuration declares, never the task: signals, mechanical units, cameras.
CONFIGURED_TYPES = SIGNAL_TYPES | frozenset({"mecunit", "cameradev"})
# Handles rather than values: a read never writes data into them.
DEVICE_TYPES = SIGNAL_TYPES | frozenset({
    "switch", "iodev", "socketdev", "intnum", "dir", "cameradev", "rmqslot", "mecunit", "egmident", "sensor",
    "triggdata", "clock", "syncident", "datapos", "pathrecid", "corrdescr", "loadsession", "testsignal", "taskid",
    "tasks", "trapdata", "shapedata", "wzstationary", "wztemporary"})


@dataclass(frozen=True)
class Param:
    """One parameter as the manual's syntax lays it out."""

    name: str  # without the backslash
    type: str  # 'num', 'signaldo', 'string', 'anytype', ...
    access: str  # 'IN' | 'VAR' | 'INOUT' | 'PERS' | 'REF' (Dim, Present, Type, ArgName: any data, read only)
    optional: bool
    switch: bool
    alt: bool  # an alternative to the parameter before it


@dataclass(frozen=True)
class Word:
    """A RAPID word and how rswarp handles it."""

    name: str  # as the manual writes it: 'SocketReceive'
    kind: str  # 'instruction' | 'function' | 'type'
    handling: str  # one of HANDLINGS
    category: str  # 'motion', 'string', 'socket', ..., or 'option: Arc' for an option's word
    params: tuple[Param, ...]
    source: str = "manual"  # 'manual' or 'option: NAME'


# Instructions and functions by handling; data types are "no-op" unless in _MODELLED_TYPES.
_HANDLING = {
    "modelled": """AccSet Add BookErrNo Break CallByVar CapC CapL Clear ClkReset ClkStart ClkStop Comment ConfJ
        ConfL Decr EXIT ExitCycle FOR GetDataVal GetSysData GOTO GripLoad IF SetDataSearch Incr InvertDO Label MoveAbsJ
        MoveC MoveCAO MoveCDO MoveCGO MoveCSync MoveJ MoveJAO MoveJDO MoveJGO MoveJSync MoveL MoveLAO MoveLDO MoveLGO
        MoveLSync ProcCall PulseDO RAISE Reset RETRY RETURN SearchC SearchL Set SetAllDataVal SetAO SetDataVal SetDO
        SetGO SetSysData Stop SyncMoveOff SyncMoveOn SyncMoveUndo TEST TriggC TriggJ TriggL TRYNEXT VelSet WaitAI
        WaitAO WaitDI WaitDO WaitGI WaitGO WaitSyncTask WaitTime WaitUntil WHILE Abs AbsDnum ACos AInput AND AOutput
        ArgName ASin ATan ATan2 BitAnd BitCheck BitLSh BitNeg BitOr BitRSh BitXOr ByteToStr CalcJointT CalcRobT
        CalcRotAxisFrame CDate CJointT ClkRead Cos CPos CRobT CrossProd CSpeedOverride CTime CTool CWObj DecToHex
        DefAccFrame DefDFrame DefFrame Dim DInput Distance DIV DnumToNum DnumToStr DotProd DOutput EulerZYX Exp
        GetMecUnitName GetNextSym GetTaskName GetTime GInput GOutput HexToDec IsMechUnitActive IsPers IsStopMoveAct
        IsSyncMoveOn IsVar MaxRobSpeed MirPos MOD ModExist NOrient NOT NumToDnum NumToStr Offs OpMode OR OrientZYX
        ORobT PoseInv PoseMult PoseVect Pow PowDnum Present RelTool RobName RobOS Round RoundDnum
        RunMode Sin Sqrt SqrtDnum StrFind StrLen StrMap StrMatch StrMemb StrOrder StrPart StrToByte StrToVal Tan
        TaskRunMec TaskRunRob TestAndSet TestDI Trunc TruncDnum Type ValidIO ValToStr VectMagn XOR ACosDnum ASinDnum
        ATanDnum ATan2Dnum BitAndDnum BitCheckDnum BitLShDnum BitNegDnum BitOrDnum BitRShDnum BitXOrDnum CosDnum
        SinDnum TanDnum GInputDnum GOutputDnum StrDigCalc StrDigCmp BitClear BitSet""",
    "no-op": """ActEventBuffer ActUnit AliasCamera AliasIO AliasIOReset CamFlush CamLoadJob CamReqImage
        CamSetExposure CamSetParameter CamSetProgramMode CamSetRunMode CamStartLoadJob CancelLoad CapAPTrSetup
        CapCondSetDO CapEquiDist CapLATrSetup CapNoProcess CapRefresh CapWeaveSync CheckProgRef CirPathMode
        ClearIOBuff ClearPath ClearRawBytes Close CloseDir CopyFile CopyRawBytes DeactEventBuffer DeactUnit
        DropSensor DropWObj EGMGetId EGMReset EGMSetupAI EGMSetupAO EGMSetupGI EGMSetupLTAPP EGMSetupUC EGMStop
        EraseModule ErrLog ErrWrite FricIdInit FricIdSetFricLevels GetTrapData HollowWristReset ICap
        IDelete IDisable IEnable IError IOBusStart IODisable IOEnable IPathPos IPers IRMQMessage ISignalAI ISignalAO
        ISignalDI ISignalDO ISignalGI ISignalGO ISleep ITimer IVarValue IWatch InitSuperv Load MakeDir MechUnitLoad
        MotionSup Open OpenDir PackDNHeader PackRawBytes PathAccLim PathRecStart PathRecStop PathResol
        ProcerrRecovery PrxActivAndStoreRecord PrxActivRecord PrxDbgStoreRecord PrxDeactRecord PrxResetPos
        PrxResetRecords PrxSetPosOffset PrxSetRecordSampleTime PrxSetSyncalarm PrxStartRecord PrxStopRecord
        PrxStoreRecord PrxUseFileRecord RMQEmptyQueue RMQFindSlot RMQSendMessage RemoveAllCyclicBool
        RemoveCyclicBool RemoveDir RemoveFile RemoveSuperv RenameFile ResetAxisDistance ResetAxisMoveTime
        ResetPPMoved ResetRetryCount RestoPath Rewind SCWrite STCalib STClose STIndGun STIndGunReset STOpen STTune
        STTuneReset SafetyControllerSyncRequest Save SaveCfgData SenDevice SetLeadThrough SetupCyclicBool
        SetupSuperv SiClose SiConnect SiSetCyclic SingArea SkipWarn SocketAccept SocketBind SocketClose
        SocketConnect SocketCreate SocketListen SocketSend SocketSendTo SoftAct SoftDeact SpyStart SpyStop StartLoad
        StartMove StartMoveRetry StopMove StopMoveReset StorePath SupSyncSensorOff SupSyncSensorOn TPErase TPShow
        TPWrite TestSignDefine TestSignReset TextTabInstall TriggCheckIO TriggDataCopy TriggDataReset TriggEquip
        TriggIO TriggInt TriggRampAO TriggSpeed TriggStopProc TryInt TuneReset TuneServo UIMsgWrite UIMsgWriteAbort
        UIShow UnLoad WZBoxDef WZCylDef WZDOSet WZDisable WZEnable WZFree WZHomeJointDef
        WZLimJointDef WZLimSup WZSphDef WaitLoad WaitRob WaitSensor WaitTestAndSet WaitWObj WarmStart WorldAccLim
        Write WriteAnyBin WriteBin WriteBlock WriteCfgData WriteRawBytes WriteStrBin WriteVar WriteVarArr""",
    "live": """CamGetParameter CamGetResult FricIdEvaluate GetJointData IOBusState ReadAnyBin ReadBlock ReadCfgData
        ReadErrData ReadRawBytes ReadVarArr RMQGetMessage RMQGetMsgData RMQGetMsgHeader RMQReadWait RMQSendWait
        SiGetCyclic SocketReceive SocketReceiveFrom TPReadDnum TPReadFK TPReadNum UIMsgBox CamGetExposure
        CamGetLoadedJob CamGetName CamNumberOfResults CapGetFailSigs EGMGetState FileSize FileTimeDnum FSSize
        GetMaxNumberOfCyclicBool GetMotorTorque GetNextCyclicBool GetNextMechUnit GetNumberOfCyclicBool
        GetServiceInfo GetSignalOrigin GetSysInfo GetTSPStatus IOUnitState IsCyclicBool IsFile ModTimeDnum
        ParIdPosValid ParIdRobValid PrxGetMaxRecordpos ReadBin ReadDir ReadMotor ReadNum ReadStr ReadStrBin ReadVar
        RMQGetSlotName SafetyControllerGetChecksum SafetyControllerGetOpModePinCode SafetyControllerGetSWVersion
        SafetyControllerGetUserChecksum SocketGetStatus SocketPeek STCalcForce STCalcTorque STIsCalib STIsClosed
        STIsIndGun STIsOpen TaskIsActive TaskIsExecuting TestSignRead TextGet TextTabGet UIAlphaEntry UIDnumEntry
        UIDnumTune UIListView UIMessageBox UINumEntry UINumTune UnpackRawBytes RawBytesLen""",
    "unmodelled": """CONNECT ContactL CorrClear CorrCon CorrDiscon CorrWrite EGMActJoint EGMActMove EGMActPose
        EGMMoveC EGMMoveL EGMRunJoint EGMRunPose EOffsOff EOffsOn EOffsSet ErrRaise FitCircle IndAMove IndCMove
        IndDMove IndReset IndRMove LoadId ManLoadIdProc MatrixSolve MatrixSolveQR MatrixSVD MotionProcessModeSet
        MoveExtJ MToolRotCalib MToolTCPCalib PathRecMoveBwd PathRecMoveFwd PDispOff PDispOn PDispSet RaiseToUser
        SearchExtJ SpeedLimAxis SpeedLimCheckPoint SpeedRefresh StepBwdPath SToolRotCalib SToolTCPCalib
        SyncMoveResume SyncMoveSuspend SyncToSensor SystemStopAction TriggJIOs TriggLIOs CalcRotAxFrameZ CorrRead
        ExecHandler GetAxisDistance GetAxisMoveTime IndInpos IndSpeed PathRecValidBwd PathRecValidFwd
        RemainingRetries TriggDataValid""",
    "state": """EventType ExecLevel GetModalPayLoadMode IsBrakeCheckActive IsLeadThrough IsStopStateEvent IsSysId
        MotionPlannerNo NonMotionMode PathLevel PFRestart PPMovedInManMode ProgMemFree TasksInSync TextTabFreeToUse
        UIClientExist""",
}
# Data types holding values the interpreter computes with (numbers, records, signals, tasks).
_MODELLED_TYPES = """ALIAS aiotrigg bool btnres busstate buttondata byte clock confdata dionum dnum errdomain errnum
    errstr errtype event_type exec_level extjoint handler_type icondata identno intnum iounit_state jointtarget
    listitem loaddata num opcalc opnum orient paridnum paridvalidnum pos pose robjoint robtarget sensorstate
    signalai signalao signaldi signaldo signalgi signalgo signalorigin signalxx socketstatus speeddata
    stoppointdata string stringdig switch symnum syncident taskid tasks tooldata triggmode tunetype wobjdata
    zonedata"""

# What a 'state' function answers offline: a controller in automatic mode running one robot's
# program, the one it was written for.
STATE_VALUES: dict[str, object] = {
    "eventtype": 0.0,  # EVENT_NONE: no event routine is running
    "execlevel": 0.0,  # LEVEL_NORMAL
    "getmodalpayloadmode": 1.0,  # the system parameter ModalPayLoadMode's default
    "isbrakecheckactive": False,
    "isleadthrough": False,
    "isstopstateevent": False,
    "issysid": True,  # the program runs on the controller whose identity it checks
    "motionplannerno": 1.0,
    "nonmotionmode": False,
    "pathlevel": 1.0,  # the base path level, not StorePath's
    "pfrestart": False,  # no power failure interrupted the path
    "ppmovedinmanmode": False,
    "progmemfree": 10e6,  # bytes: room for any module a program loads
    "tasksinsync": 0.0,
    "texttabfreetouse": True,
    "uiclientexist": True,  # a FlexPendant is connected
}

_CATEGORIES = {
    "language": "IF FOR WHILE TEST GOTO Label RETURN EXIT ExitCycle ProcCall CallByVar Comment Stop Break ALIAS switch",
    "operator": "AND OR NOT XOR DIV MOD",
    "error recovery": """RAISE RETRY TRYNEXT RaiseToUser BookErrNo ErrRaise ProcerrRecovery ResetRetryCount
        RemainingRetries ExecHandler errnum errdomain errtype handler_type""",
    "event log": "ErrLog ErrWrite SkipWarn ReadErrData errstr",
    "motion": """MoveAbsJ MoveC MoveCAO MoveCDO MoveCGO MoveCSync MoveExtJ MoveJ MoveJAO MoveJDO MoveJGO MoveJSync
        MoveL MoveLAO MoveLDO MoveLGO MoveLSync SearchC SearchExtJ SearchL ContactL TriggC TriggJ TriggL TriggJIOs
        TriggLIOs""",
    "motion data": """robtarget jointtarget robjoint extjoint confdata tooldata wobjdata loaddata speeddata zonedata
        stoppointdata motsetdata identno""",
    "motion settings": """AccSet VelSet ConfJ ConfL SingArea CirPathMode PathAccLim WorldAccLim PathResol
        MotionProcessModeSet SpeedRefresh GripLoad MechUnitLoad MotionSup SoftAct SoftDeact SetLeadThrough""",
    "path": """ClearPath StorePath RestoPath StartMove StartMoveRetry StopMove StopMoveReset PathRecMoveBwd
        PathRecMoveFwd PathRecStart PathRecStop StepBwdPath PathRecValidBwd PathRecValidFwd PathLevel IsStopMoveAct
        WaitRob ActEventBuffer DeactEventBuffer pathrecid""",
    "displacement": "PDispOn PDispOff PDispSet EOffsOn EOffsOff EOffsSet ORobT DefAccFrame DefDFrame progdisp",
    "independent axes": "IndAMove IndCMove IndDMove IndRMove IndReset IndInpos IndSpeed HollowWristReset",
    "correction": "CorrClear CorrCon CorrDiscon CorrWrite CorrRead corrdescr",
    "egm": """EGMActJoint EGMActMove EGMActPose EGMGetId EGMMoveC EGMMoveL EGMReset EGMRunJoint EGMRunPose EGMSetupAI
        EGMSetupAO EGMSetupGI EGMSetupLTAPP EGMSetupUC EGMStop EGMGetState egm_minmax egmframetype egmident
        egmstate egmstopmode""",
    "multimove": """SyncMoveOn SyncMoveOff SyncMoveUndo SyncMoveResume SyncMoveSuspend WaitSyncTask IsSyncMoveOn
        TasksInSync MotionPlannerNo syncident tasks""",
    "wait": "WaitTime WaitUntil WaitDI WaitDO WaitAI WaitAO WaitGI WaitGO",
    "io": """SetDO SetAO SetGO Set Reset PulseDO InvertDO AliasIO AliasIOReset IOBusStart IOBusState IODisable
        IOEnable DInput DOutput AInput AOutput GInput GInputDnum GOutput GOutputDnum TestDI ValidIO IOUnitState
        GetSignalOrigin signalxx signalai signalao signaldi signaldo signalgi signalgo dionum busstate iounit_state
        signalorigin""",
    "data": "Add Incr Decr Clear TestAndSet WaitTestAndSet num dnum bool byte",
    "bits": """BitSet BitClear BitAnd BitAndDnum BitCheck BitCheckDnum BitLSh BitLShDnum BitNeg BitNegDnum BitOr
        BitOrDnum BitRSh BitRShDnum BitXOr BitXOrDnum""",
    "arithmetic": """Abs AbsDnum ACos ACosDnum ASin ASinDnum ATan ATanDnum ATan2 ATan2Dnum Cos CosDnum Sin SinDnum Tan
        TanDnum Exp Pow PowDnum Sqrt SqrtDnum Round RoundDnum Trunc TruncDnum NumToDnum DnumToNum Dim TryInt
        FitCircle MatrixSolve MatrixSolveQR MatrixSVD""",
    "string": """NumToStr DnumToStr StrFind StrLen StrMap StrMatch StrMemb StrOrder StrPart StrToByte StrToVal
        ValToStr ByteToStr DecToHex HexToDec StrDigCalc StrDigCmp string stringdig opcalc""",
    "pose": """Offs RelTool OrientZYX EulerZYX PoseMult PoseInv PoseVect NOrient DefFrame Distance DotProd CrossProd
        VectMagn MirPos CalcRotAxisFrame CalcRotAxFrameZ pos orient pose""",
    "robot": """CRobT CPos CJointT CalcJointT CalcRobT CTool CWObj CSpeedOverride MaxRobSpeed GetMecUnitName
        IsMechUnitActive ActUnit DeactUnit GetNextMechUnit ReadMotor GetMotorTorque GetJointData GetAxisDistance
        GetAxisMoveTime ResetAxisDistance ResetAxisMoveTime GetServiceInfo GetModalPayLoadMode IsBrakeCheckActive
        IsLeadThrough mecunit""",
    "data by name": """GetDataVal SetDataVal SetAllDataVal SetDataSearch GetNextSym ArgName IsPers IsVar Present Type
        GetSysData SetSysData datapos symnum""",
    "interrupt": """CONNECT IDelete IDisable IEnable IError ICap IPathPos IPers IRMQMessage ISignalAI ISignalAO
        ISignalDI ISignalDO ISignalGI ISignalGO ISleep ITimer IVarValue IWatch GetTrapData intnum trapdata aiotrigg""",
    "trigger": """TriggIO TriggEquip TriggInt TriggCheckIO TriggRampAO TriggSpeed TriggStopProc TriggDataCopy
        TriggDataReset TriggDataValid triggdata triggios triggiosdnum triggmode triggstrgo restartdata""",
    "file": """Open Close Rewind Write WriteBin WriteAnyBin WriteStrBin ReadAnyBin ReadNum ReadStr ReadBin ReadStrBin
        ClearIOBuff CopyFile RemoveFile RenameFile MakeDir RemoveDir OpenDir CloseDir ReadDir IsFile FileSize
        FileTimeDnum FSSize iodev dir""",
    "raw bytes": """ClearRawBytes CopyRawBytes PackDNHeader PackRawBytes UnpackRawBytes ReadRawBytes WriteRawBytes
        RawBytesLen rawbytes""",
    "socket": """SocketAccept SocketBind SocketClose SocketConnect SocketCreate SocketListen SocketReceive
        SocketReceiveFrom SocketSend SocketSendTo SocketGetStatus SocketPeek socketdev socketstatus""",
    "flexpendant": """TPErase TPReadDnum TPReadFK TPReadNum TPShow TPWrite UIMsgBox UIMsgWrite UIMsgWriteAbort UIShow
        UIAlphaEntry UIClientExist UIDnumEntry UIDnumTune UIListView UIMessageBox UINumEntry UINumTune btnres
        buttondata icondata listitem tpnum uishownum""",
    "message queue": """RMQEmptyQueue RMQFindSlot RMQGetMessage RMQGetMsgData RMQGetMsgHeader RMQReadWait
        RMQSendMessage RMQSendWait RMQGetSlotName rmqheader rmqmessage rmqslot""",
    "clock": "ClkReset ClkStart ClkStop ClkRead CDate CTime GetTime clock",
    "program": """Load UnLoad StartLoad WaitLoad CancelLoad EraseModule Save CheckProgRef ModExist ModTimeDnum
        loadsession""",
    "text table": "TextTabInstall TextGet TextTabGet TextTabFreeToUse",
    "system": """OpMode RunMode RobOS RobName GetSysInfo IsSysId ExecLevel ProgMemFree EventType GetTaskName
        TaskRunMec TaskRunRob TaskIsActive TaskIsExecuting GetTSPStatus PPMovedInManMode ResetPPMoved PFRestart
        IsStopStateEvent NonMotionMode WarmStart SystemStopAction SpyStart SpyStop SCWrite event_type exec_level opnum
        tsp_status taskid""",
    "configuration": "ReadCfgData WriteCfgData SaveCfgData cfgdomain",
    "cyclic bool": """SetupCyclicBool RemoveCyclicBool RemoveAllCyclicBool IsCyclicBool GetNextCyclicBool
        GetNumberOfCyclicBool GetMaxNumberOfCyclicBool""",
    "world zones": """WZBoxDef WZCylDef WZDOSet WZDisable WZEnable WZFree WZHomeJointDef WZLimJointDef WZLimSup
        WZSphDef shapedata wzstationary wztemporary""",
    "vision": """CamFlush CamGetParameter CamGetResult CamLoadJob CamReqImage CamSetExposure CamSetParameter
        CamSetProgramMode CamSetRunMode CamStartLoadJob AliasCamera CamGetExposure CamGetLoadedJob CamGetName
        CamNumberOfResults cameradev cameratarget""",
    "cap": """CapAPTrSetup CapC CapCondSetDO CapEquiDist CapL CapLATrSetup CapNoProcess CapRefresh CapWeaveSync
        CapGetFailSigs InitSuperv SetupSuperv RemoveSuperv capdata caplatrackdata capspeeddata captrackdata
        capweavedata flypointdata processtimes restartblkdata weavestartdata supervtimeouts""",
    "servo tool": """STCalib STClose STIndGun STIndGunReset STOpen STTune STTuneReset STCalcForce STCalcTorque STIsCalib
        STIsClosed STIsIndGun STIsOpen""",
    "sensor": """SenDevice ReadBlock WriteBlock ReadVar WriteVar ReadVarArr WriteVarArr SiConnect SiClose SiGetCyclic
        SiSetCyclic DropSensor DropWObj WaitSensor WaitWObj SyncToSensor SupSyncSensorOn SupSyncSensorOff sensor
        sensorstate sensorvardata PrxActivAndStoreRecord PrxActivRecord PrxDbgStoreRecord PrxDeactRecord
        PrxResetPos PrxResetRecords PrxSetPosOffset PrxSetRecordSampleTime PrxSetSyncalarm PrxStartRecord
        PrxStopRecord PrxStoreRecord PrxUseFileRecord PrxGetMaxRecordpos""",
    "identification": """LoadId ManLoadIdProc ParIdPosValid ParIdRobValid FricIdInit FricIdEvaluate
        FricIdSetFricLevels loadidnum paridnum paridvalidnum""",
    "calibration": "MToolRotCalib MToolTCPCalib SToolRotCalib SToolTCPCalib",
    "servo tuning": "TuneServo TuneReset TestSignDefine TestSignReset TestSignRead tunetype testsignal",
    "safety": """SafetyControllerGetChecksum SafetyControllerGetOpModePinCode SafetyControllerGetSWVersion
        SafetyControllerGetUserChecksum SafetyControllerSyncRequest SpeedLimAxis SpeedLimCheckPoint""",
}

# The option packages' words (not in the base manual), each 'Name kind handling'; no parameters.
_OPTIONS = {
    "Arc": """ArcL instruction modelled, ArcC instruction modelled, ArcLStart instruction modelled,
        ArcLEnd instruction modelled, ArcCStart instruction modelled, ArcCEnd instruction modelled,
        ArcRefresh instruction no-op, ArcKill instruction no-op, welddata type modelled, seamdata type no-op,
        weavedata type no-op, trackdata type no-op""",
    "Spot": """SpotL instruction modelled, SpotJ instruction modelled, SpotML instruction unmodelled,
        spotdata type no-op, gundata type no-op""",
    "Paint": """PaintL instruction modelled, PaintC instruction modelled, SetBrush instruction no-op,
        SetBrushFac instruction no-op""",
    "Dispense": "DispL instruction unmodelled, DispC instruction unmodelled, beaddata type no-op, equipdata type no-op",
    "Force Control": """FCAct instruction unmodelled, FCDeact instruction no-op, FCPress1LStart instruction unmodelled,
        FCPressL instruction unmodelled, FCPressC instruction unmodelled, FCPressEnd instruction unmodelled,
        FCCalib instruction no-op, FCLoadID instruction unmodelled, FCCondForce instruction no-op,
        FCCondPos instruction no-op, FCCondOrient instruction no-op, FCCondTCPSpeed instruction no-op,
        FCCondTorque instruction no-op, FCCondReoriSpeed instruction no-op, FCCondWaitWhile instruction unmodelled,
        FCRefStart instruction unmodelled, FCRefStop instruction no-op, FCRefLine instruction no-op,
        FCRefCircle instruction no-op, FCRefRot instruction no-op, FCRefSpiral instruction no-op,
        FCRefForce instruction no-op, FCRefTorque instruction no-op, FCRefSprForceCart instruction no-op,
        FCRefMoveFrame instruction no-op, FCSupvForce instruction no-op, FCSupvPos instruction no-op,
        FCSupvOrient instruction no-op, FCSupvTCPSpeed instruction no-op, FCSupvTorque instruction no-op,
        FCSupvReoriSpeed instruction no-op, FCSpdChgAct instruction unmodelled, FCSpdChgDeact instruction no-op,
        FCSpdChgTunSet instruction no-op, FCSpdChgTunReset instruction no-op, FCSetDampingTune instruction no-op,
        FCResetDampingTune instruction no-op, FCSetMaxForceChangeTune instruction no-op,
        FCGetProcessData instruction live, FCGetForce function live, FCIsForceMode function live,
        fcboxvol type no-op, fccylindervol type no-op, fcspherevol type no-op, fcforcevector type no-op,
        fcframe type no-op, fcxyznum type no-op, fccondstatus type no-op, fcprocessdata type no-op""",
    "SmartTac": "Search_1D instruction unmodelled, Search_Groove instruction unmodelled, searchdata type no-op",
    "BullsEye": """BECheckTcp instruction unmodelled, BEUpdateTcp instruction unmodelled,
        BETcpExtend instruction unmodelled, bedata type no-op""",
    "PickMaster": """PmAckTarget instruction no-op, PmGetTarget instruction live, PmGetTgtAction instruction live,
        PmGetWorkArea instruction live, PmGetWaByWobj instruction live, PmGetEvent instruction live,
        PmGetFlowInfo instruction live, PmRemAllTargets instruction no-op, PmWaitProjStart instruction no-op,
        PmDoAction instruction no-op, PmStartProj instruction no-op, PmStopProj instruction no-op""",
    "EGM": "EGMStreamStart instruction no-op, EGMStreamStop instruction no-op",
    "SoftMove": """CSSAct instruction no-op, CSSDeact instruction no-op, CSSForceOffsetAct instruction no-op,
        CSSForceOffsetDeact instruction no-op""",
}


def _labels(table: dict[str, str]) -> dict[str, str]:
    """Lower-case name -> its label, from label -> names; a name under two labels is an error."""
    out: dict[str, str] = {}
    for label, names in table.items():
        for name in names.split():
            if out.setdefault(name.lower(), label) != label:
                raise ValueError(f"{name} is both {out[name.lower()]} and {label}")
    return out


def _param(text: str) -> Param:
    """``name:type:access[:flags]`` as words.tsv writes a parameter."""
    name, type_, access, *flags = text.split(":")
    f = flags[0] if flags else ""
    return Param(name, type_, access, "o" in f, "s" in f, "a" in f)


def _manual() -> list[tuple[str, str, tuple[Param, ...]]]:
    """(name, kind, params) of each line of words.tsv."""
    text = resources.files(__package__).joinpath("words.tsv").read_text(encoding="utf-8")
    rows = []
    for line in text.splitlines():
        if line and not line.startswith("#"):
            name, kind, *rest = line.split("\t")
            rows.append((name, kind, tuple(_param(p) for p in (rest[0].split() if rest else ()))))
    return rows


def _options() -> list[Word]:
    """The option packages' words, as their own rows."""
    out = []
    for option, rows in _OPTIONS.items():
        for row in rows.split(","):
            name, kind, handling = row.split()
            out.append(Word(name, kind, handling, f"option: {option}", (), f"option: {option}"))
    return out


@functools.lru_cache(maxsize=1)
def words() -> dict[str, Word]:
    """Every word, keyed by its lower-case name: the manual's, then the options'."""
    handling, category = _labels(_HANDLING), _labels(_CATEGORIES)
    handling.update({t: "modelled" for t in _MODELLED_TYPES.lower().split()})
    out, missing = {}, []
    for name, kind, params in _manual():
        key = name.lower()
        how = handling.get(key, "no-op" if kind == "type" else None)
        if how is None or key not in category:
            missing.append(name)
        out[key] = Word(name, kind, how or "", category.get(key, ""), params)
    if missing:
        raise ValueError(f"words without a handling or a category: {', '.join(missing)}")
    for w in _options():
        out.setdefault(w.name.lower(), w)
    return out


def word(key: str) -> Word | None:
    """The word of that lower-case name, None for one neither the manual nor an option defines."""
    return words().get(key)


def positions(key: str) -> tuple[tuple[Param, ...], ...]:
    """The required parameters by the position their argument takes, alternatives together
    (Add's Name | Dname is position 0)."""
    w = word(key)
    out: list[list[Param]] = []
    for p in w.params if w is not None else ():
        if not p.optional:
            if p.alt and out:
                out[-1].append(p)
            else:
                out.append([p])
    return tuple(tuple(group) for group in out)


def signal_params(key: str) -> tuple[int, ...]:
    """Positions among the required arguments where the word takes a signal (SetDO's 0), or another
    object the configuration declares (ActUnit's mechanical unit)."""
    return tuple(k for k, group in enumerate(positions(key)) if any(p.type in CONFIGURED_TYPES for p in group))


def signal_options(key: str) -> frozenset[str]:
    """Lower-case names of the optional parameters taking a signal (TPReadNum's 'dibreak')."""
    w = word(key)
    return frozenset(p.name.lower() for p in (w.params if w else ()) if p.optional and p.type in CONFIGURED_TYPES)


def outputs(key: str) -> tuple[Param, ...]:
    """The parameters a read writes into: VAR and INOUT ones of value types, not devices (a
    function's output is its value)."""
    w = word(key)
    return tuple(p for p in (w.params if w else ()) if p.access in ("VAR", "INOUT") and p.type not in DEVICE_TYPES)


def markdown() -> str:
    """The docs' table: for each handling, a line per category naming its words."""
    lines = []
    for how in HANDLINGS:
        chosen = [w for w in words().values() if w.handling == how]
        lines += ["", f"**{how}** ({len(chosen)}): {MEANINGS[how]}.", ""]
        groups: dict[str, list[str]] = {}
        for w in chosen:
            groups.setdefault(w.category, []).append(f"{w.name}()" if w.kind == "function" else w.name)
        for category in sorted(groups, key=lambda c: (c.startswith("option: "), c)):
            lines.append(f"- *{category}*: {', '.join(sorted(groups[category], key=str.lower))}")
    return "\n".join(lines[1:]) + "\n"


if __name__ == "__main__":
    print(markdown(), end="")
